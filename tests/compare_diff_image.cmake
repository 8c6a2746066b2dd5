# `facet compare A B --diff D.png` exits 1 for different images and writes D.png; comparing D with
# itself matches. -D FACET=... -D OUT=... -D GOLDEN=...
file(REMOVE ${OUT}/diff.png)
execute_process(COMMAND ${FACET} compare ${GOLDEN}/default_flat.png ${GOLDEN}/default_phong.png --diff ${OUT}/diff.png
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT EXISTS ${OUT}/diff.png)
  message(FATAL_ERROR "compare --diff: exit ${rc}, ${out} ${err}")
endif()
execute_process(COMMAND ${FACET} compare ${OUT}/diff.png ${OUT}/diff.png RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "match")
  message(FATAL_ERROR "the difference image does not read back: ${out}")
endif()
# Identical images give an all-black difference: it matches an image of zeros written by a black render.
execute_process(COMMAND ${FACET} compare ${GOLDEN}/default_flat.png ${GOLDEN}/default_flat.png --diff ${OUT}/same.png
                RESULT_VARIABLE rc)
execute_process(COMMAND ${FACET} compare ${OUT}/same.png ${OUT}/diff.png RESULT_VARIABLE rc2 OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT rc2 EQUAL 1)
  message(FATAL_ERROR "identical images: exit ${rc}; their difference image equals the other's (exit ${rc2}): ${out}")
endif()
message("compare --diff writes difference images")

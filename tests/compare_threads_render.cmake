# `facet render --threads N` writes byte-identical PNG files for N = 1, 2 and 8 (issue: determinism
# for any thread count), for each shading mode of the built-in scene.
# -D FACET=... -D OUT=...
foreach(shading flat gouraud phong)
  foreach(threads 1 2 8)
    execute_process(COMMAND ${FACET} render -o ${OUT}/threads_${shading}_${threads}.png --shading ${shading}
                            --threads ${threads} --width 400 --height 240 --tile 32
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "render failed: ${err}")
    endif()
  endforeach()
  foreach(threads 2 8)
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/threads_${shading}_1.png
                            ${OUT}/threads_${shading}_${threads}.png RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${shading}: the PNG with --threads ${threads} differs from --threads 1")
    endif()
  endforeach()
endforeach()
message("flat, gouraud, phong: PNG files identical for --threads 1, 2, 8")

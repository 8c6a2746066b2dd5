# Renders the built-in scene with --path simd --isa ${ISA} and compares it with the reference
# render (cli.render_reference) within 1 step. A CPU without the ISA prints
# "this CPU does not have it", which the test reports as skipped.
execute_process(COMMAND ${FACET} render -o ${OUT}/simd_${ISA}.png --path simd --isa ${ISA} --width 320 --height 180
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message("${err}")
  if(err MATCHES "this CPU does not have it")
    return()
  endif()
  message(FATAL_ERROR "render failed")
endif()
execute_process(COMMAND ${FACET} compare ${OUT}/simd_${ISA}.png ${OUT}/reference.png --tolerance 1
                RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "simd ${ISA} differs from the reference by more than 1 step")
endif()

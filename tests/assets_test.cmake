# Regenerates the bundled assets and compares them with the committed ones.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${GENERATOR} ${OUT} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the generator failed (${rc}): ${err}")
endif()
foreach(f meshes/head.ply meshes/torso.ply maps/hair_length.png)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DATA}/${f} ${OUT}/${f} RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "data/${f} differs from what data/generators/make_assets.cpp makes; "
                        "regenerate with: build/release/data/loosehair_make_assets data")
  endif()
endforeach()
# The bundled styles, made on the regenerated head (identical to data/'s).
execute_process(COMMAND ${STYLE_GENERATOR} ${OUT} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the style generator failed (${rc}): ${err}")
endif()
foreach(s long-straight bob side-swept swept-back wavy ponytail)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DATA}/styles/${s}.json ${OUT}/styles/${s}.json
                  RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "data/styles/${s}.json differs from what data/generators/make_styles.cpp makes; "
                        "regenerate with: build/release/data/loosehair_make_styles data")
  endif()
endforeach()

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

# The windowed viewer under a virtual X server (xvfb-run): it opens a window,
# draws the scene (the screenshot is not blank) and plays the same
# simulation as the headless program (equal state hashes after N frames).
# -DVIEW=<loosehair-view> -DLOOSEHAIR=<loosehair> -DXVFB_RUN=<xvfb-run> -DSCENE=<json> -DOUT=<dir>
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
set(frames 4)
execute_process(COMMAND "${XVFB_RUN}" -a -s "-screen 0 640x480x24" "${VIEW}" "${SCENE}" --frames ${frames}
    --threads 2 --size 320x240 --screenshot "${OUT}/shot.png"
  RESULT_VARIABLE rc OUTPUT_VARIABLE view_out ERROR_VARIABLE view_err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "loosehair-view failed (${rc}):\n${view_out}\n${view_err}")
endif()
if(NOT EXISTS "${OUT}/shot.png")
  message(FATAL_ERROR "no screenshot written:\n${view_out}")
endif()
string(REGEX MATCH "screenshot: [^\n]*\\(320x240, ([0-9]+)% of the picture drawn" m "${view_out}")
if(NOT m OR CMAKE_MATCH_1 LESS 5)
  message(FATAL_ERROR "the screenshot is (almost) blank:\n${view_out}")
endif()
string(REGEX MATCH "state-hash: ([0-9a-f]+)" m "${view_out}")
set(view_hash "${CMAKE_MATCH_1}")
execute_process(COMMAND "${LOOSEHAIR}" simulate "${SCENE}" --frames ${frames} --threads 2
  RESULT_VARIABLE rc OUTPUT_VARIABLE sim_out ERROR_VARIABLE sim_err)
string(REGEX MATCH "state-hash: ([0-9a-f]+)" m "${sim_out}")
set(sim_hash "${CMAKE_MATCH_1}")
if(NOT rc EQUAL 0 OR NOT view_hash STREQUAL sim_hash)
  message(FATAL_ERROR "the viewer's state (${view_hash}) differs from the headless run's (${sim_hash})\n${view_out}\n${sim_out}")
endif()
message(STATUS "viewer: ${view_out}")

# --allow-expensive: a scene beyond a cost limit (more than 2000 steps a
# frame) is refused with the limit and the option named, and opens with it.
file(READ "${SCENE}" scene_text)
string(REGEX REPLACE "\"substeps\": [0-9]+" "\"substeps\": 2001" scene_text "${scene_text}")
string(REGEX REPLACE "\"frames\": [0-9]+" "\"frames\": 1" scene_text "${scene_text}")
if(NOT scene_text MATCHES "\"substeps\": 2001")
  message(FATAL_ERROR "the test scene ${SCENE} gives no substeps to raise")
endif()
file(WRITE "${OUT}/expensive.json" "${scene_text}")
execute_process(COMMAND "${XVFB_RUN}" -a -s "-screen 0 640x480x24" "${VIEW}" "${OUT}/expensive.json" --frames 1
    --threads 2 --size 320x240
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "expensive.json: substeps: 2001" OR NOT err MATCHES "limit of 2000"
   OR NOT err MATCHES "--allow-expensive")
  message(FATAL_ERROR "a scene beyond the cost limits was not refused as expected (${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND "${XVFB_RUN}" -a -s "-screen 0 640x480x24" "${VIEW}" "${OUT}/expensive.json" --frames 1
    --threads 2 --size 320x240 --allow-expensive
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "2001 substeps a frame")
  message(FATAL_ERROR "--allow-expensive did not open the scene (${rc}):\n${out}\n${err}")
endif()

# Hardening, round two, as a user meets it on the command line: outputs
# that are not files are refused before anything is written (a FIFO, a
# directory, /dev/null, which as root a rename would replace), --video names
# ffmpeg could misread, an import that would overwrite its input or write
# half its outputs, crafted snapshots, wrong files given as scenes, and the
# options' spellings (--flag=value, suggestions for typos).
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_support.cmake)
function(says text pattern what)
  if(NOT text MATCHES "${pattern}")
    message(FATAL_ERROR "${what}: expected /${pattern}/ in:\n${text}")
  endif()
endfunction()

# ---- outputs that are not files --------------------------------------------------
execute_process(COMMAND mkfifo ${OUT}/fifo RESULT_VARIABLE rc)
if(rc EQUAL 0)
  run(1 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --save-state ${OUT}/fifo)
  says("${err}" "fifo: is a FIFO .named pipe., not a file to write; nothing was written" "--save-state FIFO")
  # refused before the run: no frame was simulated
  if(out MATCHES "simulated")
    message(FATAL_ERROR "--save-state to a FIFO was refused only after the run:\n${out}")
  endif()
endif()
file(MAKE_DIRECTORY ${OUT}/folder)
run(1 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --save-state ${OUT}/folder)
says("${err}" "folder: is a directory, not a file to write" "--save-state directory")
run(1 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --save-state /dev/null)
says("${err}" "/dev/null: is a character device, not a file to write" "--save-state /dev/null")
execute_process(COMMAND test -c /dev/null RESULT_VARIABLE still_device)
if(NOT still_device EQUAL 0)
  message(FATAL_ERROR "/dev/null is no longer a character device")
endif()

# ---- --video names ffmpeg could read as something else -----------------------------
foreach(bad "tcp://127.0.0.1:45678/x.mp4:looks like a URL" "file:f.mp4:looks like a URL"
    "${OUT}/out.avi:writes .mp4, .m4v, .mov or .mkv" "/dev/null:writes .mp4")
  string(FIND "${bad}" ":" cut REVERSE)
  string(SUBSTRING "${bad}" 0 ${cut} name)
  math(EXPR from "${cut} + 1")
  string(SUBSTRING "${bad}" ${from} -1 pattern)
  run(1 ${LOOSEHAIR} render ${SCENE} --frames 1 --size 32x32 --out ${OUT}/v --overwrite --video "${name}")
  says("${err}" "${pattern}" "--video ${name}")
endforeach()
if(EXISTS ${OUT}/v/frame_00001.png)
  message(FATAL_ERROR "a refused --video still rendered frames")
endif()
# names that are files: an option-like name and "file:" behind ./, and a
# Matroska video that is one
run(0 ${LOOSEHAIR} render ${SCENE} --frames 2 --size 32x32 --out ${OUT}/v1 --video ${OUT}/-y.mp4)
run(0 ${LOOSEHAIR} render ${SCENE} --frames 2 --size 32x32 --out ${OUT}/v2 --video=${OUT}/clip.mkv)
file(READ ${OUT}/clip.mkv magic LIMIT 4 HEX)
if(NOT magic STREQUAL "1a45dfa3")
  message(FATAL_ERROR "clip.mkv is not a Matroska file (it starts ${magic})")
endif()
file(READ ${OUT}/-y.mp4 magic OFFSET 4 LIMIT 4 HEX)
if(NOT magic STREQUAL "66747970")  # "ftyp"
  message(FATAL_ERROR "-y.mp4 is not an MP4 file")
endif()
file(GLOB left ${OUT}/*tmp*)
if(left)
  message(FATAL_ERROR "temporary files were left: ${left}")
endif()

# ---- style --import: outputs that are inputs, all or nothing ------------------------
run(0 ${LOOSEHAIR} style ${STYLE} --strands ${OUT}/groom.hair)
# (a copy beside the outputs, its mesh paths made absolute)
get_filename_component(scene_dir ${HEAD_SCENE} DIRECTORY)
file(READ ${HEAD_SCENE} scene_text)
string(REPLACE "\"../" "\"${scene_dir}/../" scene_text "${scene_text}")
file(WRITE ${OUT}/head-scene.json "${scene_text}")
file(READ ${OUT}/head-scene.json scene_before)
run(2 ${LOOSEHAIR} style --import ${OUT}/groom.hair --head ${OUT}/head-scene.json --out ${OUT}/head-scene.json)
says("${err}" "--out .*head-scene.json is the file given to --head" "--out the --head scene")
run(2 ${LOOSEHAIR} style --import ${OUT}/groom.hair --head ${OUT}/head-scene.json --out ${OUT}/x.json
    --strands ${OUT}/groom.hair)
says("${err}" "--strands .*groom.hair is the file given to --import" "--strands the groom")
file(READ ${OUT}/head-scene.json scene_after)
if(NOT scene_before STREQUAL scene_after)
  message(FATAL_ERROR "the --head scene was changed")
endif()
# a --strands that cannot be written: neither file is written
run(1 ${LOOSEHAIR} style --import ${OUT}/groom.hair --head ${OUT}/head-scene.json --out ${OUT}/imported.json
    --strands ${OUT}/folder)
if(EXISTS ${OUT}/imported.json)
  message(FATAL_ERROR "the style was written although the strands were not")
endif()
run(0 ${LOOSEHAIR} style --import ${OUT}/groom.hair --head ${OUT}/head-scene.json --out ${OUT}/imported.json
    --strands ${OUT}/imported.obj)
run(0 ${LOOSEHAIR} style ${OUT}/imported.json)

# ---- crafted snapshots ------------------------------------------------------------------
# the step count of a real snapshot set to 2^63, the checksum recomputed by
# the test (FNV-1a 64 over all bytes before it): refused, not "-143... frames"
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --save-state ${OUT}/run.state)
if(PYTHON3)
  execute_process(COMMAND ${PYTHON3} -c "
import struct, sys
b = bytearray(open(sys.argv[1], 'rb').read())
b[48:56] = struct.pack('<Q', 1 << 63)
h = 0xcbf29ce484222325
for c in b[:-8]:
    h = ((h ^ c) * 0x100000001b3) & 0xffffffffffffffff
b[-8:] = struct.pack('<Q', h)
open(sys.argv[2], 'wb').write(b)
" ${OUT}/run.state ${OUT}/crafted.state RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "could not craft the snapshot")
  endif()
  run(1 ${LOOSEHAIR} simulate ${SCENE} --resume ${OUT}/crafted.state)
  says("${err}" "crafted.state: not a usable snapshot: the step count is 9223372036854775808" "crafted snapshot")
endif()

# ---- wrong files as scenes, and the options' spellings -------------------------------------
run(1 ${LOOSEHAIR} render ${STYLE} --frames 1)
says("${err}" "is a style file .it has \"wisps\"., not a scene; .*--style" "render STYLE")
run(1 ${LOOSEHAIR} render ${HEAD_MESH} --frames 1)
says("${err}" "is a mesh, not a scene" "render head.ply")
if(err MATCHES "json.exception")
  message(FATAL_ERROR "a raw parser message: ${err}")
endif()
run(2 ${LOOSEHAIR} render ${SCENE} --frame 3)
says("${err}" "unknown option --frame .did you mean --frames\\?." "--frame")
run(2 ${LOOSEHAIR} render ${SCENE} --colour red)
says("${err}" "did you mean --color\\?" "--colour")
run(2 ${LOOSEHAIR} simulate ${SCENE} --seeds 3)
says("${err}" "did you mean --seed\\?" "--seeds")
# render's --out, named in simulate's help, is not simulate's: no "did you mean --out?"
run(2 ${LOOSEHAIR} simulate ${SCENE} --out x)
says("${err}" "unknown option --out .not an option of this command." "simulate --out")
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames=3 --threads=2)
says("${out}" "simulated 0.100 s" "--frames=3")
# one default strand count for simulate and render
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 1 --dump-strands ${OUT}/strands)
says("${out}" "render strands: 1[12][0-9][0-9][0-9] of 24 points" "simulate --dump-strands default")
run(0 ${LOOSEHAIR} render ${SCENE} --frames 1 --size 32x32 --out ${OUT}/r)
says("${out}" "hair: 1[12][0-9][0-9][0-9] strands of 24 points" "render default")
# render --motion: the saved motion replaces the scene's
file(WRITE ${OUT}/nod.json "{\"motion\": {\"type\": \"nod\", \"amplitude_deg\": 20, \"frequency_hz\": 2}}")
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 3 --motion ${OUT}/nod.json)
string(REGEX MATCH "state-hash: [0-9a-f]+" with_motion "${out}")
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 3)
string(REGEX MATCH "state-hash: [0-9a-f]+" without "${out}")
if(with_motion STREQUAL without)
  message(FATAL_ERROR "--motion did not change the run")
endif()
run(0 ${LOOSEHAIR} render ${SCENE} --frames 1 --size 32x32 --out ${OUT}/m --motion ${OUT}/nod.json)
message(STATUS "hardening: every case refused or done as expected")

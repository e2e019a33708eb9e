# What `loosehair` writes tells the truth: snapshots resume bit-identically
# from the command line, a full disk (a file-size limit) is an error with no
# partial file left, --video starts ffmpeg without a shell, dump directories
# of an earlier run are refused without --overwrite, and --help / --version
# work for every command.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

include(${CMAKE_CURRENT_LIST_DIR}/cli_test_support.cmake)
function(hash_of text var)
  string(REGEX MATCH "state-hash: ([0-9a-f]+)" m "${text}")
  set(${var} "${CMAKE_MATCH_1}" PARENT_SCOPE)
endfunction()

# --help and --version
foreach(cmd simulate render)
  run(0 ${LOOSEHAIR} ${cmd} --help)
  string(FIND "${out}" "usage: loosehair ${cmd}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${cmd} --help printed no usage: ${out}")
  endif()
endforeach()
run(0 ${LOOSEHAIR} --version)
if(NOT out MATCHES "^loosehair [0-9]+\\.[0-9]+\\.[0-9]+")
  message(FATAL_ERROR "--version printed '${out}'")
endif()

# snapshots: 4 frames + 3 frames resumed == 7 frames
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 7)
hash_of("${out}" whole)
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 4 --save-state ${OUT}/run.state --save-every 2)
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 3 --resume ${OUT}/run.state)
hash_of("${out}" resumed)
if(NOT whole STREQUAL resumed OR whole STREQUAL "")
  message(FATAL_ERROR "resumed run ends at ${resumed}, the whole run at ${whole}")
endif()
# a damaged snapshot is refused, naming the file
file(WRITE ${OUT}/bad.state "loosehair-state\nnot really")
run(1 ${LOOSEHAIR} simulate ${SCENE} --frames 1 --resume ${OUT}/bad.state)
if(NOT err MATCHES "bad.state: .*truncated")
  message(FATAL_ERROR "unclear error for a damaged snapshot: ${err}")
endif()

# a dump directory of an earlier run: refused, then replaced with --overwrite
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 3 --dump ${OUT}/dump)
run(1 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --dump ${OUT}/dump)
if(NOT err MATCHES "not empty.*--overwrite")
  message(FATAL_ERROR "a non-empty dump directory was not refused clearly: ${err}")
endif()
run(0 ${LOOSEHAIR} simulate ${SCENE} --frames 2 --dump ${OUT}/dump --overwrite)
file(GLOB frames ${OUT}/dump/*)
list(LENGTH frames count)
if(NOT count EQUAL 2)
  message(FATAL_ERROR "--overwrite left ${count} files, expected the 2 new frames: ${frames}")
endif()

# shell metacharacters in --video and --out are only names
set(weird "${OUT}/it's \$(touch ${OUT}/PWNED) %d")
run(0 ${LOOSEHAIR} render ${SCENE} --frames 2 --size 32x32 --out "${weird}"
    --video "${OUT}/x' && touch ${OUT}/PWNED2 && echo '.mp4")
if(EXISTS ${OUT}/PWNED OR EXISTS ${OUT}/PWNED2)
  message(FATAL_ERROR "a file name was run as a command")
endif()
if(NOT EXISTS "${OUT}/x' && touch ${OUT}/PWNED2 && echo '.mp4")
  message(FATAL_ERROR "the video with a strange name was not written")
endif()

# a full disk, imitated by a file-size limit (bash: ulimit -f, SIGXFSZ
# ignored so that writes fail with EFBIG): exit 1, no partial file
if(BASH)
  foreach(what "render;--out;${OUT}/full-frames" "render;--video;${OUT}/full.mp4" "simulate;--dump;${OUT}/full-dump"
      "simulate;--dump-strands;${OUT}/full-strands")
    list(GET what 0 cmd)
    list(GET what 1 flag)
    list(GET what 2 target)
    set(extra "")
    if(flag STREQUAL "--video")
      set(extra "--out ${OUT}/full-video-frames")
    endif()
    if(cmd STREQUAL "render")
      # large enough that a frame (and the video) is more than the limit
      set(extra "${extra} --size 400x300")
    endif()
    execute_process(COMMAND ${BASH} -c
        "trap '' XFSZ; ulimit -f 24; exec \"$0\" ${cmd} \"$1\" --frames 6 ${extra} ${flag} \"$2\""
        ${LOOSEHAIR} ${SCENE} ${target}
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 1)
      message(FATAL_ERROR "${cmd} ${flag} on a full disk exited ${rc}: ${err}")
    endif()
    file(GLOB_RECURSE left ${OUT}/full*)
    foreach(f IN LISTS left)
      file(SIZE ${f} size)
      if(f MATCHES "tmp" OR size EQUAL 0)
        message(FATAL_ERROR "a partial file was left: ${f} (${size} bytes)")
      endif()
    endforeach()
    if(flag STREQUAL "--video" AND EXISTS ${target})
      message(FATAL_ERROR "a video was left although ffmpeg could not finish it")
    endif()
  endforeach()
endif()

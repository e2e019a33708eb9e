# Writes OUT, a header with each GLSL file in SHADER_DIR as a string
# constant loosehair::render::shaders::<file name with . as _>.
# cmake -DOUT=<header> -DSHADER_DIR=<dir> -P embed_shaders.cmake
file(GLOB SHADERS LIST_DIRECTORIES false "${SHADER_DIR}/*")
list(SORT SHADERS)
set(text "// Generated from render/shaders/ by render/embed_shaders.cmake: do not edit.\n#pragma once\n\nnamespace loosehair::render::shaders {\n")
foreach(path IN LISTS SHADERS)
  get_filename_component(name "${path}" NAME)
  string(MAKE_C_IDENTIFIER "${name}" id)
  file(READ "${path}" body)
  if(body MATCHES "\\)glsl\"")
    message(FATAL_ERROR "${path}: contains the raw-string delimiter )glsl\"")
  endif()
  string(APPEND text "inline constexpr const char ${id}[] = R\"glsl(${body})glsl\";\n")
endforeach()
string(APPEND text "}  // namespace loosehair::render::shaders\n")
# rewritten only when it changes, so sources that include it rebuild only then
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()

# Packs shader files into one C++ source: a table of {name, text} that
# yv::shaderSource(name) looks up. Each text starts with a #line marker so
# driver errors point at the real file.
function(yv_embed_shaders output)
  set(inputs ${ARGN})
  set(abs_inputs)
  foreach(f ${inputs})
    list(APPEND abs_inputs ${CMAKE_CURRENT_SOURCE_DIR}/${f})
  endforeach()
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} "-DINPUTS=${abs_inputs}"
            -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/EmbedShadersRun.cmake
    DEPENDS ${abs_inputs} ${CMAKE_CURRENT_SOURCE_DIR}/cmake/EmbedShadersRun.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
endfunction()

# Packs source files into one C++ source at build time, through a run script
# (cmake/Embed*Run.cmake) that writes the table: the shaders (a {name, text}
# table that yv::shaderSource(name) looks up, each text behind a #line marker
# so driver errors point at the real file) and the view's page (yv::pageFile).
function(yv_embed_files output run_script comment)
  set(abs_inputs)
  foreach(f ${ARGN})
    list(APPEND abs_inputs ${CMAKE_CURRENT_SOURCE_DIR}/${f})
  endforeach()
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} "-DINPUTS=${abs_inputs}"
            -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/${run_script}
    DEPENDS ${abs_inputs} ${CMAKE_CURRENT_SOURCE_DIR}/cmake/${run_script}
    COMMENT "${comment}"
    VERBATIM)
endfunction()

# Packs the files of `yarnvox view`'s page (page/) into one C++ source: a
# table of {name, text} that yv::pageFile(name) looks up (src/view/page_files.h),
# the way cmake/EmbedShaders.cmake packs the shaders.
function(yv_embed_page output)
  set(abs_inputs)
  foreach(f ${ARGN})
    list(APPEND abs_inputs ${CMAKE_CURRENT_SOURCE_DIR}/${f})
  endforeach()
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} "-DINPUTS=${abs_inputs}"
            -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/EmbedPageRun.cmake
    DEPENDS ${abs_inputs} ${CMAKE_CURRENT_SOURCE_DIR}/cmake/EmbedPageRun.cmake
    COMMENT "Embedding the view page"
    VERBATIM)
endfunction()

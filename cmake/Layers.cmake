# One static library per layer folder of src/, each compiled against a view
# of the source tree that holds only its own folder and the layers below it:
#
#   yv_layer(NAME gpu SOURCES ... BELOW plan [LINK ...])
#
# makes `yv_gpu` from the sources, links the libraries of the layers named in
# BELOW (and so theirs), and compiles it with the include directory
# build/layer-views/gpu/, where `core/`, `garment/`, `plan/` and `gpu/` are
# links into src/ and nothing else is. `#include "pipeline/x.h"` from a file of
# src/gpu/ then fails to compile: an include that runs up the layers is a
# build error, not a review comment. docs/architecture.md draws the layers.
#
# `formats` (the garment file's reader, formats/bcc.h, included as "bcc.h") is
# a layer too; the layers that may read garments see its folder.

set(YV_LAYER_VIEWS ${CMAKE_BINARY_DIR}/layer-views)

function(yv_layer)
  cmake_parse_arguments(L "" "NAME" "SOURCES;BELOW;LINK" ${ARGN})
  set(visible ${L_NAME})
  foreach(below IN LISTS L_BELOW)
    get_property(below_visible GLOBAL PROPERTY YV_LAYER_VISIBLE_${below})
    if(NOT below_visible)
      message(FATAL_ERROR "layer ${L_NAME}: layer ${below} is not defined before it")
    endif()
    list(APPEND visible ${below_visible})
  endforeach()
  list(REMOVE_DUPLICATES visible)
  set_property(GLOBAL PROPERTY YV_LAYER_VISIBLE_${L_NAME} ${visible})

  set(view ${YV_LAYER_VIEWS}/${L_NAME})
  file(REMOVE_RECURSE ${view})
  file(MAKE_DIRECTORY ${view})
  set(include_dirs ${view})
  foreach(layer IN LISTS visible)
    if(layer STREQUAL "formats")
      list(APPEND include_dirs ${CMAKE_SOURCE_DIR}/formats)
    else()
      file(CREATE_LINK ${CMAKE_SOURCE_DIR}/src/${layer} ${view}/${layer} SYMBOLIC)
    endif()
  endforeach()

  add_library(yv_${L_NAME} STATIC ${L_SOURCES})
  target_include_directories(yv_${L_NAME} PRIVATE ${include_dirs})
  list(TRANSFORM L_BELOW PREPEND yv_ OUTPUT_VARIABLE below_libraries)
  target_link_libraries(yv_${L_NAME} PUBLIC ${below_libraries} ${L_LINK} PRIVATE yv_warnings)
endfunction()

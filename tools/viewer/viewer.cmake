# Included by tools/CMakeLists.txt: the sources of `nrsfm view`
# (NRSFM_VIEWER_SOURCES, added to the nrsfm binary).
#
# Every page `nrsfm view` writes inlines three.js r111 and its OrbitControls
# from Debian's libjs-three; they, the page template and its script are
# embedded into the binary at build time (embed.cmake), so a page needs no
# file at run time.
set(NRSFM_THREE_DIR /usr/share/javascript/three CACHE PATH
    "Folder of three.js (Debian libjs-three) for nrsfm view")
find_file(NRSFM_THREE_JS three.min.js PATHS ${NRSFM_THREE_DIR} NO_DEFAULT_PATH)
find_file(NRSFM_ORBIT_CONTROLS_JS OrbitControls.js
  PATHS ${NRSFM_THREE_DIR}/examples/js/controls NO_DEFAULT_PATH)
if(NOT NRSFM_THREE_JS OR NOT NRSFM_ORBIT_CONTROLS_JS)
  message(FATAL_ERROR "nrsfm view needs three.js: three.min.js and "
    "examples/js/controls/OrbitControls.js under NRSFM_THREE_DIR = ${NRSFM_THREE_DIR} "
    "(apt-get install libjs-three), or configure with -DNRSFM_BUILD_TOOLS=OFF")
endif()

set(_viewer_dir ${CMAKE_CURRENT_LIST_DIR})
set(_viewer_assets ${CMAKE_CURRENT_BINARY_DIR}/viewer_assets.cc)
add_custom_command(OUTPUT ${_viewer_assets}
  COMMAND ${CMAKE_COMMAND} -DOUTPUT=${_viewer_assets}
          -DPAGE_HTML=${_viewer_dir}/page.html -DVIEWER_UTIL_JS=${_viewer_dir}/viewer_util.js
          -DVIEWER_JS=${_viewer_dir}/viewer.js
          -DTHREE_JS=${NRSFM_THREE_JS} -DORBIT_CONTROLS_JS=${NRSFM_ORBIT_CONTROLS_JS}
          -P ${_viewer_dir}/embed.cmake
  DEPENDS ${_viewer_dir}/page.html ${_viewer_dir}/viewer_util.js ${_viewer_dir}/viewer.js
          ${_viewer_dir}/embed.cmake
          ${NRSFM_THREE_JS} ${NRSFM_ORBIT_CONTROLS_JS}
  COMMENT "Embedding the nrsfm view page and three.js"
  VERBATIM)

set(NRSFM_VIEWER_SOURCES
  ${CMAKE_CURRENT_SOURCE_DIR}/view_command.cc
  ${CMAKE_CURRENT_SOURCE_DIR}/view_data.cc
  ${CMAKE_CURRENT_SOURCE_DIR}/view_frame_images.cc
  ${CMAKE_CURRENT_SOURCE_DIR}/view_page.cc
  ${_viewer_assets})

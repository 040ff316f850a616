# The web build (make web): the library and app/web/ compiled to
# WebAssembly by emscripten (emcmake cmake ...; included from
# CMakeLists.txt when CMAKE_SYSTEM_NAME is Emscripten).  No emscripten
# ports: libpng is not linked (app/web/no_png.c answers the PNG calls with
# an error; the page encodes its screenshots with the browser) and the page
# draws into a canvas, so SDL is not needed either.
#
# Two builds of the same sources: edgewise.js/.wasm with -pthread (the
# renderer's bands on Web Workers over a SharedArrayBuffer, for a page that
# is cross-origin isolated) and edgewise-st.js/.wasm without (one thread,
# for a page that is not).  The page picks one (app/web/page.js).
set(EW_WEB_OUT ${CMAKE_BINARY_DIR}/web CACHE PATH "Where make web puts the page")
file(GLOB EW_WEB_LIB_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/*.c ${CMAKE_SOURCE_DIR}/src/*/*.c)
list(FILTER EW_WEB_LIB_SOURCES EXCLUDE REGEX "/src/output/png\\.c$")
file(GLOB EW_WEB_APP_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/app/web/*.c ${CMAKE_SOURCE_DIR}/app/common/*.c)


set(EW_WEB_EXPORTS "['_main','_malloc','_free']")
set(EW_WEB_RUNTIME "['FS','ccall','cwrap','UTF8ToString','stringToUTF8','lengthBytesUTF8']")
foreach(variant st mt)
  add_library(edgewise_web_${variant} STATIC ${EW_WEB_LIB_SOURCES})
  target_include_directories(edgewise_web_${variant} PUBLIC ${CMAKE_SOURCE_DIR}/include
                             PRIVATE ${CMAKE_SOURCE_DIR}/src ${CMAKE_SOURCE_DIR}/src/mapgen)
  # WebAssembly SIMD: the span drawers' four-lane loops (src/ew_simd.h),
  # which the native build runs as SSE2.  Every browser the page asks for
  # (SharedArrayBuffer, Workers) has it.
  target_compile_options(edgewise_web_${variant} PUBLIC -msimd128)
  if(variant STREQUAL "st")
    set(out edgewise-st)
  else()
    set(out edgewise)
    target_compile_options(edgewise_web_${variant} PUBLIC -pthread)
  endif()
  add_executable(edgewise_web_app_${variant} ${EW_WEB_APP_SOURCES})
  target_include_directories(edgewise_web_app_${variant} PRIVATE ${CMAKE_SOURCE_DIR}/app/common)
  target_link_libraries(edgewise_web_app_${variant} PRIVATE edgewise_web_${variant} m)
  set_target_properties(edgewise_web_app_${variant} PROPERTIES OUTPUT_NAME ${out} SUFFIX ".js"
                        RUNTIME_OUTPUT_DIRECTORY ${EW_WEB_OUT})
  target_link_options(edgewise_web_app_${variant} PRIVATE
    -sMODULARIZE=1 -sEXPORT_NAME=EdgewiseModule -sALLOW_MEMORY_GROWTH=1 -sINITIAL_MEMORY=67108864
    -sMAXIMUM_MEMORY=2147483648 -sEXPORTED_RUNTIME_METHODS=${EW_WEB_RUNTIME}
    -sEXPORTED_FUNCTIONS=${EW_WEB_EXPORTS} -sFORCE_FILESYSTEM=1 -sENVIRONMENT=web,worker)
  if(variant STREQUAL "mt")
    # The workers are made while the page loads (PTHREAD_POOL_SIZE), one
    # per logical processor the browser reports, so the renderer's
    # pthread_create never waits for a worker to start on the main thread.
    target_link_options(edgewise_web_app_${variant} PRIVATE -pthread -Wno-pthreads-mem-growth
      "-sPTHREAD_POOL_SIZE=Math.min(64,Math.max(1,(typeof navigator!=='undefined'&&navigator.hardwareConcurrency)||1))")
  endif()
endforeach()

# The page's own files, copied beside the two builds.
set(EW_WEB_PAGE_FILES index.html page.js serve.mjs)
set(EW_WEB_PAGE_OUT "")
foreach(f ${EW_WEB_PAGE_FILES})
  add_custom_command(OUTPUT ${EW_WEB_OUT}/${f}
    COMMAND ${CMAKE_COMMAND} -E copy ${CMAKE_SOURCE_DIR}/app/web/${f} ${EW_WEB_OUT}/${f}
    DEPENDS ${CMAKE_SOURCE_DIR}/app/web/${f})
  list(APPEND EW_WEB_PAGE_OUT ${EW_WEB_OUT}/${f})
endforeach()
add_custom_target(edgewise_web_page ALL DEPENDS ${EW_WEB_PAGE_OUT})

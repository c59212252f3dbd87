# INTERFACE helper targets linked PRIVATE by every motionblocks target (STYLE.md).
add_library(mb_warnings INTERFACE)
target_compile_options(mb_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
  -Wold-style-cast -Wnon-virtual-dtor)
if(MB_WERROR)
  target_compile_options(mb_warnings INTERFACE -Werror)
endif()

add_library(mb_sanitizers INTERFACE)
if(MB_SANITIZE)
  target_compile_options(mb_sanitizers INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                         -fno-sanitize-recover=undefined)
  target_link_options(mb_sanitizers INTERFACE -fsanitize=address,undefined)
endif()
if(MB_FUZZ)
  # Coverage instrumentation for libFuzzer in every library; the fuzz targets link -fsanitize=fuzzer.
  target_compile_options(mb_sanitizers INTERFACE -fsanitize=fuzzer-no-link)
endif()

add_library(mb_options INTERFACE)
target_link_libraries(mb_options INTERFACE mb_warnings mb_sanitizers)
target_compile_definitions(mb_options INTERFACE JSON_DIAGNOSTICS=1)

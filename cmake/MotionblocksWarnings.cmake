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
  if(NOT MB_FUZZ)
    # The test build leaves out UBSan's two checks made at every load and store. With ASan they made the numerical
    # code (Eigen's products, the FFT, the scans) 2.0 x slower again (gemv and gemm on 25,000 x 12, GCC 12: 0.25 s
    # plain, 0.98 s ASan, 2.19 s ASan + UBSan, 1.11 s without these two). ASan reports a null dereference itself (a
    # SEGV at address 0); the fuzz build, which runs the readers of untrusted files where a misaligned load could
    # hide, keeps both.
    target_compile_options(mb_sanitizers INTERFACE -fno-sanitize=alignment,null)
  endif()
elseif(MB_SANITIZE_UNDEFINED)
  # make test's build (the test preset): UBSan alone, optimised, the same two checks left out as above. Its runtime
  # needs no preloading (unlike ASan's), so the Python module and the command line run as in Release.
  # Two false warnings of GCC 12 flood this build's log: -Warray-bounds inside nlohmann-json's std::map (Release has a
  # few, UBSan's checks make them a hundred) and -Wsign-conversion at a C array's int index under -fsanitize=bounds.
  # Off here; the Release and asan builds keep both.
  target_compile_options(mb_sanitizers INTERFACE -fsanitize=undefined -fno-sanitize-recover=undefined
                         -fno-sanitize=alignment,null -Wno-array-bounds -Wno-sign-conversion)
  target_link_options(mb_sanitizers INTERFACE -fsanitize=undefined)
endif()
if(MB_FUZZ)
  # Coverage instrumentation for libFuzzer in every library; the fuzz targets link -fsanitize=fuzzer.
  target_compile_options(mb_sanitizers INTERFACE -fsanitize=fuzzer-no-link)
endif()

add_library(mb_options INTERFACE)
target_link_libraries(mb_options INTERFACE mb_warnings mb_sanitizers)
target_compile_definitions(mb_options INTERFACE JSON_DIAGNOSTICS=1)

# FindHIL: the Quanser HIL SDK (C API: hil.h; libraries hil, quanser_runtime, quanser_common).
# The SDK comes from Quanser's own repository (https://github.com/quanser/hil_sdk_linux_x86_64 or the Quanser
# SDK installer), never from Debian and never vendored here; it installs to /opt/quanser/hil_sdk.
#
# Hints: HIL_ROOT (CMake or environment variable) pointing at the SDK folder that holds include/ and lib/.
# Defines: HIL_FOUND, HIL_INCLUDE_DIR, HIL_LIBRARIES, and the imported target HIL::hil.

find_path(HIL_INCLUDE_DIR hil.h
  HINTS ${HIL_ROOT} ENV HIL_ROOT
  PATHS /opt/quanser/hil_sdk /usr/local/quanser/hil_sdk
  PATH_SUFFIXES include)

foreach(component hil quanser_runtime quanser_common)
  find_library(HIL_${component}_LIBRARY ${component}
    HINTS ${HIL_ROOT} ENV HIL_ROOT
    PATHS /opt/quanser/hil_sdk /usr/local/quanser/hil_sdk
    PATH_SUFFIXES lib lib64)
endforeach()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(HIL
  REQUIRED_VARS HIL_INCLUDE_DIR HIL_hil_LIBRARY HIL_quanser_runtime_LIBRARY HIL_quanser_common_LIBRARY
  REASON_FAILURE_MESSAGE
    "install the Quanser HIL SDK (it goes to /opt/quanser/hil_sdk) or point HIL_ROOT at it; see docs/hil.md")

if(HIL_FOUND)
  set(HIL_LIBRARIES ${HIL_hil_LIBRARY} ${HIL_quanser_runtime_LIBRARY} ${HIL_quanser_common_LIBRARY})
  if(NOT TARGET HIL::hil)
    add_library(HIL::hil INTERFACE IMPORTED)
    # The SDK's examples link: -lhil -lquanser_runtime -lquanser_common -lrt -lpthread -ldl -lm
    set_target_properties(HIL::hil PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${HIL_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${HIL_LIBRARIES};rt;Threads::Threads;${CMAKE_DL_LIBS};m")
  endif()
endif()
mark_as_advanced(HIL_INCLUDE_DIR HIL_hil_LIBRARY HIL_quanser_runtime_LIBRARY HIL_quanser_common_LIBRARY)

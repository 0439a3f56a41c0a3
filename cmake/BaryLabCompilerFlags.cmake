# Warning and sanitizer flags, applied per target through barylab_set_flags(target).
add_library(barylab_flags INTERFACE)
target_compile_options(barylab_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wshadow=local -Wnon-virtual-dtor>)
if(BARYLAB_SANITIZE)
  target_compile_options(barylab_flags INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(barylab_flags INTERFACE -fsanitize=address,undefined)
endif()

function(barylab_set_flags target)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:barylab_flags>)
endfunction()

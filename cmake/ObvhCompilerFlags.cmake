# Warnings and optimisation flags shared by every obvh target.
set(CMAKE_CXX_FLAGS_RELEASE "-O3 -DNDEBUG")
set(CMAKE_C_FLAGS_RELEASE "-O3 -DNDEBUG")

add_library(obvh_warnings INTERFACE)
target_compile_options(obvh_warnings INTERFACE -Wall -Wextra -Wno-unused-parameter)

# Global build settings in one place.
set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

# Products round before they are added, on every CPU: the vector kernels and their portable twins
# must give the same bits. GCC contracts a * b + c into an FMA by default in C++ (-std=c++20 turns
# that off only for C) wherever a target allows FMA.
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  add_compile_options(-ffp-contract=off)
endif()

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE RelWithDebInfo CACHE STRING "Build type" FORCE)
endif()

option(HAPTEX_WERROR "Treat warnings in project code as errors" ON)
set(HAPTEX_SANITIZE "" CACHE STRING "Sanitizers for project code, e.g. address,undefined or thread")

# Warnings apply to project targets only (through haptex_set_warnings), never to generated code.
set(HAPTEX_WARNING_FLAGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
    -Wcast-align -Wunused -Woverloaded-virtual -Wdouble-promotion -Wformat=2
    -Wimplicit-fallthrough)
if(HAPTEX_WERROR)
  list(APPEND HAPTEX_WARNING_FLAGS -Werror)
  # GCC 12 reports false -Wrestrict positives inside libstdc++'s std::string at -O3 (GCC bug
  # 105329): keep the warning, but do not let it fail Release builds.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    list(APPEND HAPTEX_WARNING_FLAGS -Wno-error=restrict)
  endif()
endif()

if(HAPTEX_SANITIZE)
  add_compile_options(-fsanitize=${HAPTEX_SANITIZE} -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${HAPTEX_SANITIZE})
  add_compile_definitions(HAPTEX_SANITIZED=1)
endif()

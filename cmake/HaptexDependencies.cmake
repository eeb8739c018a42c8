# Every dependency is a Debian package (scripts/setup installs them); nothing is fetched at build time.
find_package(Threads REQUIRED)
find_package(Protobuf REQUIRED)
find_package(spdlog REQUIRED)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(CLI11 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(SODIUM REQUIRED IMPORTED_TARGET libsodium)

# Standalone Asio is header-only.
find_path(ASIO_INCLUDE_DIR asio.hpp REQUIRED)
add_library(haptex_asio INTERFACE)
target_include_directories(haptex_asio SYSTEM INTERFACE ${ASIO_INCLUDE_DIR})
target_compile_definitions(haptex_asio INTERFACE ASIO_STANDALONE ASIO_NO_DEPRECATED)
target_link_libraries(haptex_asio INTERFACE Threads::Threads)
add_library(haptex::asio ALIAS haptex_asio)

find_program(GNUPLOT_EXECUTABLE gnuplot)
find_program(CLANGXX_EXECUTABLE NAMES clang++ clang++-14)

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

# The viewer's WebSocket server: websocketpp (header-only) over standalone Asio, JSON by nlohmann.
# A target of its own, not haptex::asio: websocketpp 0.8.2 uses Asio's deprecated names
# (io_service, work), which ASIO_NO_DEPRECATED removes. It does not parse as C++20 either
# (template-id constructors), so the targets that include it build as C++17 (services/viewer).
find_path(WEBSOCKETPP_INCLUDE_DIR websocketpp/version.hpp REQUIRED)
find_package(nlohmann_json 3.2 REQUIRED)
add_library(haptex_websocketpp INTERFACE)
target_include_directories(haptex_websocketpp SYSTEM INTERFACE ${WEBSOCKETPP_INCLUDE_DIR} ${ASIO_INCLUDE_DIR})
target_compile_definitions(haptex_websocketpp INTERFACE ASIO_STANDALONE _WEBSOCKETPP_CPP11_STL_)
target_link_libraries(haptex_websocketpp INTERFACE Threads::Threads)
add_library(haptex::websocketpp ALIAS haptex_websocketpp)

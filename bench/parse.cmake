# bench_parse: lexes and parses a generated ~50 MB scene; prints MB/s and peak RSS.
add_executable(bench_parse ${CMAKE_CURRENT_SOURCE_DIR}/parse/bench_parse.cpp)
target_link_libraries(bench_parse PRIVATE snell_language snell_warnings)

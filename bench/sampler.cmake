# bench_sampler: ns per draw of each sampler kind and its ratio to independent,
# with a checksum of the numbers drawn (equal checksums: the same numbers).
add_executable(bench_sampler ${CMAKE_CURRENT_LIST_DIR}/sampler/bench_sampler.cpp)
target_include_directories(bench_sampler PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_sampler PRIVATE snell_runtime snell_warnings)

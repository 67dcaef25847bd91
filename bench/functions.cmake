# bench_functions: what a §15 shading function costs against the same pattern
# written in C++ (the ratio per case, measured in one run).
add_executable(bench_functions ${CMAKE_CURRENT_LIST_DIR}/functions/bench_functions.cpp)
target_include_directories(bench_functions PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_functions PRIVATE snell_compiler snell_pattern snell_warnings)

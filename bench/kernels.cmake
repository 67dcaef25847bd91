# bench_kernels: general ÷ specialised render time per example scene, one run.
add_executable(bench_kernels ${CMAKE_CURRENT_LIST_DIR}/kernels/bench_kernels.cpp)
target_include_directories(bench_kernels PRIVATE ${PROJECT_SOURCE_DIR})
target_compile_definitions(bench_kernels PRIVATE
  SNELL_EXAMPLES_DIR="${PROJECT_SOURCE_DIR}/examples")
target_link_libraries(bench_kernels PRIVATE snell_compiler snell_runtime snell_warnings)

# bench_trace: Snell's traced rays/s on built-in scenes next to a raw Embree driver
# for the same scene and ray mix, and 1 vs 2 threads. Prints ratios from one run.
add_executable(bench_trace ${CMAKE_CURRENT_LIST_DIR}/trace/bench_trace.cpp)
target_include_directories(bench_trace PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_trace PRIVATE snell_runtime embree TBB::tbb fmt::fmt snell_warnings)
# The kernel-specialisation benchmark lives beside this one (bench/CMakeLists.txt
# lists only trace.cmake of the two).
include(${CMAKE_CURRENT_LIST_DIR}/kernels.cmake)

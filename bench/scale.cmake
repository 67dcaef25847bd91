# bench_scale: a scene of many spheres and one of a million-triangle mesh, from the
# text to the traced rays: compile time and IR memory per object, build time,
# memory while rendering, rays/s with 1 and 2 threads (#17 scale, #18 memory).
add_executable(bench_scale ${CMAKE_CURRENT_LIST_DIR}/scale/bench_scale.cpp)
target_include_directories(bench_scale PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_scale PRIVATE snell_compiler snell_runtime snell_warnings)

# bench_interiors: the cost of §14's interior tracking (priorities against the
# core's explicit interfaces for the same picture), from one run.
add_executable(bench_interiors ${CMAKE_CURRENT_LIST_DIR}/interiors/bench_interiors.cpp)
target_include_directories(bench_interiors PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_interiors PRIVATE snell_compiler snell_runtime snell_warnings)

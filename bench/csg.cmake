# bench_csg: what §12 CSG costs per camera sample against the plain shapes it is
# made of, and what §13 instances save in memory and build time against copies,
# from one run.
add_executable(bench_csg ${CMAKE_CURRENT_LIST_DIR}/csg/bench_csg.cpp)
target_include_directories(bench_csg PRIVATE ${PROJECT_SOURCE_DIR})
target_link_libraries(bench_csg PRIVATE snell_compiler snell_runtime snell_warnings)

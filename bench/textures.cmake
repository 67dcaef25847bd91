# bench_textures: what a §17 image lookup costs per hit against an untextured and
# a checkered surface, and the texture cache's figures, from one run.
add_executable(bench_textures ${CMAKE_CURRENT_LIST_DIR}/textures/bench_textures.cpp)
target_include_directories(bench_textures PRIVATE ${PROJECT_SOURCE_DIR})
# OIIO only to write the bench's own image (the runtime reaches it through the module).
target_link_libraries(bench_textures PRIVATE snell_compiler snell_runtime snell_warnings
                      OpenImageIO::OpenImageIO)

# One 3 s run of the paper's conventional FF/FB/DOB loop (3,000 control steps at Ts = 1 ms) on the linear-motor
# twin. Numbers in docs/benchmarks.md ("Closed loop").
mb_add_benchmark(closed_loop_benchmark SOURCES ${PROJECT_SOURCE_DIR}/tests/benchmarks/closed_loop_benchmark.cc
                 LIBS mb_engine mb_blocks mb_stability)
target_compile_definitions(closed_loop_benchmark PRIVATE MB_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# Sweeps: runs per second on 1 and 2 threads, cost per run against its stop time (tools/batch). Numbers in
# docs/benchmarks.md ("Sweeps"); the MPI ranks by scripts/bench_sweep_mpi.sh.
mb_add_benchmark(sweep_benchmark SOURCES ${PROJECT_SOURCE_DIR}/tests/benchmarks/sweep_benchmark.cc
                 LIBS mb_batch mb_blocks)
target_compile_definitions(sweep_benchmark PRIVATE MB_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# TISO-GPR: MAP fit (both solvers) and prediction per call. Numbers: docs/benchmarks.md.
mb_add_benchmark(gpr_benchmark SOURCES ${PROJECT_SOURCE_DIR}/tests/benchmarks/gpr_benchmark.cc
                 LIBS mb_gpr)

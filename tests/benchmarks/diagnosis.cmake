# The diagnosis on an independent 25k-sample log: compare (goal < 1 s) and improve (goal < 20 s). Numbers:
# docs/benchmarks.md ("Diagnosis").
mb_add_benchmark(diagnosis_benchmark SOURCES ${PROJECT_SOURCE_DIR}/tests/benchmarks/diagnosis_benchmark.cc
                 LIBS mb_independent_bench mb_blocks)

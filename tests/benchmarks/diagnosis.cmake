# The diagnosis on an independent 25k-sample log: compare (goal < 1 s), compare in simulation mode (goal < 5 s) and
# improve (goal < 20 s). Numbers:
# docs/benchmarks.md ("Diagnosis").
mb_add_benchmark(diagnosis_benchmark SOURCES ${PROJECT_SOURCE_DIR}/tests/benchmarks/diagnosis_benchmark.cc
                 LIBS mb_independent_bench mb_blocks)
target_compile_definitions(diagnosis_benchmark PRIVATE MB_SOURCE_DIR="${PROJECT_SOURCE_DIR}")  # the closed-loop diagram

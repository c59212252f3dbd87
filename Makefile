# The two commands of the README. Both install what they need (Debian packages) and build from scratch.
JOBS ?= $(shell nproc)

.PHONY: deps build demo test test-asan bench bench-diagnosis bench-diagnosis-simulation bench-grammar clean

deps:
	./scripts/install-deps.sh

build: deps
	cmake --preset release
	cmake --build --preset release -j $(JOBS)

## make demo: the main job on the embedded default (real EMPS data): compare, diagnose, add the effect, validate.
demo: build
	./scripts/demo.sh build/release/tools/motionblocks

## make test: every GoogleTest suite, the Python module's, the README's commands and figures, the reports in a browser and
## the hostile inputs, built optimised (-O2) under UndefinedBehaviorSanitizer and libstdc++'s assertions (the test
## preset); then the fuzzers of the file readers under ASan + UBSan (clang, briefly: only the fuzz targets and the
## libraries they link are built there, at -O1 with line tables only, as libFuzzer's documentation builds them;
## 19,000-62,000 inputs per fuzzer in its 20 s). The whole suite under AddressSanitizer is `make test-asan`: an hour and
## more on 2 cores, over CI's limit (docs/benchmarks.md, "Build and test time").
test: deps
	cmake --preset test
	cmake --build --preset test -j $(JOBS)
	ctest --preset test
	cmake --preset fuzz
	cmake --build --preset fuzz -j $(JOBS) --target fuzzers
	ctest --preset fuzz

## make test-asan: the same suites under AddressSanitizer + UBSan (the asan preset).
test-asan: deps
	cmake --preset asan
	cmake --build --preset asan -j $(JOBS)
	ctest --preset asan

bench: build
	./scripts/bench.sh

## make bench-diagnosis: the independent hidden-effect cases (tests/diagnosis/independent_bench.h), Release: the table
## of docs/diagnosis.md ("Independent hidden-effect cases").
bench-diagnosis:
	cmake --preset release
	cmake --build --preset release -j $(JOBS) --target bench_diagnosis
	build/release/tests/diagnosis/bench_diagnosis --out=out/bench-diagnosis

## make bench-diagnosis-simulation: the same cases compared in simulation mode with the closed-loop diagram of the
## generator's loop (tests/diagnosis/data/independent_closed_loop.json), compare only, then the clean records at 1 kHz,
## 100 Hz and 2 kHz with 20 seeds each: docs/diagnosis.md ("Simulation mode"). Fails when either misses.
bench-diagnosis-simulation:
	cmake --preset release
	cmake --build --preset release -j $(JOBS) --target bench_diagnosis
	build/release/tests/diagnosis/bench_diagnosis --simulation --compare-only --out=out/bench-diagnosis-simulation; \
	  cases=$$?; \
	  build/release/tests/diagnosis/bench_diagnosis --simulation --compare-only --clean-seeds=20 \
	    --out=out/bench-diagnosis-simulation-clean; \
	  clean=$$?; exit $$((cases | clean))

## make bench-grammar: random draws from the diagnosis' grammar (tests/diagnosis/grammar_bench.h), Release: 300 draws,
## 50 noise-only ones and 60 with memory (hysteresis, a drifting vibration) diagnosed and improved; the confusion table
## of docs/diagnosis.md ("Random draws from the grammar"). Then seeds 301-600 compared: seeds 1-300 are the ones the
## diagnosis was developed on, and these the ones it was not ("Seeds it was not developed on"), the figure that says
## how far it generalises.
bench-grammar:
	cmake --preset release
	cmake --build --preset release -j $(JOBS) --target bench_grammar
	build/release/tests/diagnosis/bench_grammar --memory=60 --out=out/bench-grammar
	build/release/tests/diagnosis/bench_grammar --first-seed=301 --draws=300 --noise=0 --compare-only \
	  --out=out/bench-grammar-validation

clean:
	rm -rf build

# The two commands of the README. Both install what they need (Debian packages) and build from scratch.
JOBS ?= $(shell nproc)

.PHONY: deps build demo test bench clean

deps:
	./scripts/install-deps.sh

build: deps
	cmake --preset release
	cmake --build --preset release -j $(JOBS)

## make demo: the main job on the embedded default (real EMPS data): compare, diagnose, add the effect, validate.
demo: build
	./scripts/demo.sh build/release/tools/motionblocks

## make test: every GoogleTest suite under ASan + UBSan, then the fuzzers of the file readers (clang, briefly).
test: deps
	cmake --preset asan
	cmake --build --preset asan -j $(JOBS)
	ctest --preset asan
	cmake --preset fuzz
	cmake --build --preset fuzz -j $(JOBS)
	ctest --preset fuzz

bench: build
	./scripts/bench.sh

clean:
	rm -rf build

# jnd — top-level driver. The real build is CMake; these targets are the README's commands.
#   make demo   install deps, build, run `jnd diff` on a built-in synthetic pair
#   make test   install deps, build with -Werror, run the unit + end-to-end suite,
#               then the same suite under ASan + UBSan, then each fuzzer briefly
#   make bench  speed and memory figures, with peer tools where present
#   make fuzz   build the libFuzzer targets and run each for FUZZ_SECONDS
#   make asan   the suite under AddressSanitizer + UndefinedBehaviorSanitizer
#   make mutants  each mutation of tests/mutants.txt applied to a scratch copy,
#               rebuilt and tested: fails unless the suite catches every one
#   make python  the Python package `jnd` (python/), built into build/python
#   make install PREFIX=/usr/local
SHELL := /bin/bash
BUILD ?= build
ASAN_BUILD ?= build-asan
FUZZ_BUILD ?= build-fuzz
MUTANTS_BUILD ?= build-mutants
JOBS ?= $(shell nproc)
PREFIX ?= /usr/local
FUZZ_SECONDS ?= 20
CMAKE_FLAGS ?=

.PHONY: all deps build demo test unit asan fuzz fuzz-build bench install clean mutants mutants-ci python

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DJND_WERROR=ON $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	@mkdir -p demo
	$(BUILD)/jnd example -o demo
	$(BUILD)/jnd diff demo/reference.png demo/test.png --display standard-fhd \
	    --json demo/diff.json --heatmap demo/heatmap.png --map demo/jnd.exr
	@echo "demo: wrote demo/diff.json, demo/heatmap.png and demo/jnd.exr"

unit: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test: unit asan fuzz

# intercept_tls_get_addr=0: clang 14's __tls_get_addr interceptor takes a
# malloc'd dynamic TLS block that happens to sit 16 bytes into a page for a
# glibc < 2.25 header and reads a bogus range from it; LeakSanitizer's tracer
# then segfaults scanning it at exit ("Tracer caught signal 11"), at random,
# in any test that loads Mesa. Dynamic TLS stays reachable (and scanned)
# through the thread's DTV, so leaks are still found.
asan: deps
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DJND_WERROR=ON -DJND_SANITIZE=ON \
	    -DCMAKE_C_COMPILER=clang $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 \
	    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 JND_SANITIZED=1 \
	    ctest --output-on-failure -j $(JOBS) -LE slow

fuzz-build: deps
	@cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=Debug -DJND_FUZZ=ON \
	    -DCMAKE_C_COMPILER=clang $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(FUZZ_BUILD) -j $(JOBS)

fuzz: fuzz-build
	@bash fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

mutants: deps
	@MUTANTS_DIR=$(MUTANTS_BUILD) JOBS=$(JOBS) bash scripts/mutants.sh

# CI's share (.ci/run): every entry checked for stale text, the [ci] sections run
mutants-ci: deps
	@bash scripts/mutants.sh --check
	@MUTANTS_DIR=$(MUTANTS_BUILD) JOBS=$(JOBS) bash scripts/mutants.sh --ci

bench: build
	@bash bench/run.sh $(BUILD)

# the Python package, built into $(BUILD)/python (also part of `make build`)
python: build
	@echo "python: PYTHONPATH=$(BUILD)/python /usr/bin/python3 -c 'import jnd; print(jnd.version())'"
	@PYTHONPATH=$(BUILD)/python /usr/bin/python3 -c 'import jnd; print("jnd", jnd.version())'

install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) $(MUTANTS_BUILD)

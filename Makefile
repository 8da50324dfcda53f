# Entry points for building, testing, benchmarking and the demo. See README.md.
#   make demo       compression report of the bundled sunset environment map
#   make test       Release build + all tests
#   make test-asan  AddressSanitizer + UBSan build (build-asan/) + all tests
#   make bench      run every build/bin/bench_* program, JSON into bench/results/
# Each of these first runs `make deps` (scripts/install-deps, a no-op when all is installed).

JOBS ?= 2
BUILD_DIR ?= build
ASAN_DIR ?= build-asan
RESULTS_DIR ?= bench/results
# Extra flags for every benchmark program, e.g. BENCH_ARGS=--benchmark_min_time=0.1
BENCH_ARGS ?=
DEMO_INPUT ?= data/envmaps/sunset_1024x512.exr

# Ninja when available; the generator is only chosen when a build directory is first configured
# (CMake refuses to switch generators in an existing one).
GENERATOR := $(if $(shell command -v ninja 2>/dev/null),-G Ninja,)
generator_for = $(if $(wildcard $(1)/CMakeCache.txt),,$(GENERATOR))

SANITIZER_ENV := ASAN_OPTIONS=halt_on_error=1:print_stacktrace=1:detect_leaks=1 \
                 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

.PHONY: all deps configure build test configure-asan build-asan test-asan demo bench clean

all: build

deps:
	scripts/install-deps

configure:
	cmake -S . -B $(BUILD_DIR) $(call generator_for,$(BUILD_DIR)) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: deps
	$(MAKE) build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

configure-asan:
	cmake -S . -B $(ASAN_DIR) $(call generator_for,$(ASAN_DIR)) \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DACDF_SANITIZE=address,undefined

build-asan: configure-asan
	cmake --build $(ASAN_DIR) -j $(JOBS)

test-asan: deps
	$(MAKE) build-asan
	$(SANITIZER_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS)

demo: deps
	$(MAKE) build
	$(BUILD_DIR)/bin/acdf cdf-stats $(DEMO_INPUT)

bench: deps
	$(MAKE) build
	@mkdir -p $(RESULTS_DIR)
	@set -e; found=0; \
	for prog in $(BUILD_DIR)/bin/bench_*; do \
	  [ -f "$$prog" ] && [ -x "$$prog" ] || continue; \
	  found=1; name=$$(basename "$$prog"); \
	  echo "== $$name -> $(RESULTS_DIR)/$$name.json"; \
	  "$$prog" --benchmark_out="$(RESULTS_DIR)/$$name.json" --benchmark_out_format=json $(BENCH_ARGS); \
	done; \
	if [ $$found -eq 0 ]; then echo "bench: no benchmark programs in $(BUILD_DIR)/bin (bench_*)" >&2; exit 1; fi

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR)

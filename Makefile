# Entry points for building, testing, benchmarking and the demo. See README.md.
#   make demo       render scenes/demo.json and scenes/product.json (no strategy named: the defaults),
#                   then the compression report of the sunset map and the paper's Table 1 rows for
#                   the demo's three measured materials
#   make test       Release build + all tests (the Python suite also on the package pip installs
#                   from a wheel, in a fresh virtual environment)
#   make test-asan  AddressSanitizer + UBSan build (build-asan/) + all tests
#   make bench      run every build/bin/bench_* program, JSON into bench/results/, and their tables in
#                   docs/performance.md; bench/bench_python.py (the Python module against the C++
#                   loop); the paper's Table 1 rows in docs/paper-reproduction.md; then
#                   acdf bench-error on scenes/demo.json into bench/results/error/ (BENCH_ERROR_ARGS)
#                   and its section of docs/performance.md with the plots in docs/bench-error/
#   make fuzz       libFuzzer targets (clang, build-fuzz/), each for FUZZ_SECONDS
#   make stress     numerical stress program (1e8 samples per distribution; STRESS_ARGS)
#   make test-tsan  ThreadSanitizer build (build-tsan/) + the multithreaded tests
#   make install    the libraries, headers and CMake package (find_package(acdf)) into PREFIX
#   make bench-peers  acdf against Cycles 5 and Mitsuba 3 at equal time on the example scenes (bench/peers/,
#                   PEERS_ARGS; docs/performance.md's last section), after make bench-peers-check, the test of
#                   the scene conversion's conventions; both install .venv-peers first (scripts/install-peers:
#                   PyPI's bpy, about 1 GB). Neither is part of make test or CI
#   make test-wheel-portable  the repaired (manylinux) wheel in a fresh Debian 12 root with only
#                   Python and pip: import, sample, the Mitsuba example (root and debootstrap)
# Each of these first runs `make deps` (scripts/install-deps, a no-op when all is installed).

JOBS ?= 2
PREFIX ?= /usr/local
BUILD_DIR ?= build
ASAN_DIR ?= build-asan
RESULTS_DIR ?= bench/results
# Extra flags for every benchmark program, e.g. BENCH_ARGS=--benchmark_min_time=0.1
BENCH_ARGS ?=
DEMO_INPUT ?= data/envmaps/sunset_1024x512.exr
# make bench's error-against-time run (acdf bench-error on scenes/demo.json): three MIS modes
# (balance behaves like power), four environment tables (pbrt-v4's uniform one, our adaptive,
# compensated and local ones), independent and Sobol samples, budgets up to 2 s, each rendered
# with 4 seeds for error bars: 14 s of rendering a combination, about 15 minutes on 2 cores. A
# stopped run resumes. The full matrix (every strategy, both samplers, 1-16 s, 4 seeds, about 4
# hours): BENCH_ERROR_ARGS="--sampler independent,sobol" (docs/performance.md).
BENCH_ERROR_DIR ?= $(RESULTS_DIR)/error
BENCH_ERROR_ARGS ?= --budgets 0.5,1,2 --seeds 4 --mis power,bsdf-only,light-only \
  --env-sampling uniform,adaptive,compensated,local --sampler independent,sobol --reference-spp 1024
BENCH_ERROR_COMMAND = $(BUILD_DIR)/bin/acdf bench-error scenes/demo.json --out $(BENCH_ERROR_DIR) $(BENCH_ERROR_ARGS)
# The demo's measured materials, generated from the bundled neural fits (35 MB each, not in git).
# scenes/demo.json refers to them as ../build/demo/*.binary, so they live there whatever BUILD_DIR.
DEMO_DIR := build/demo
DEMO_BRDFS := nickel blue-metallic-paint specular-blue-phenolic
DEMO_BRDF_SAMPLES ?= 1024
FUZZ_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
# libFuzzer's random seed: fixed, so a CI run can be replayed; FUZZ_SEED=0 picks a new one each run.
FUZZ_SEED ?= 1
# One target by hand: make build-fuzz FUZZ_TARGETS=rgl, then run $(FUZZ_DIR)/bin/fuzz_rgl on a
# corpus directory or an input file.
FUZZ_TARGETS := engine cascade merl image npy scene rgl
TSAN_DIR ?= build-tsan
STRESS_ARGS ?= --samples 1e8 --json $(RESULTS_DIR)/stress.json

# Ninja when available; the generator is only chosen when a build directory is first configured
# (CMake refuses to switch generators in an existing one).
GENERATOR := $(if $(shell command -v ninja 2>/dev/null),-G Ninja,)
generator_for = $(if $(wildcard $(1)/CMakeCache.txt),,$(GENERATOR))

# ccache, when installed, for the Release build: ctest python.pip_installed builds the wheel in a
# second build directory beside it ($(BUILD_DIR)-wheel) with the same compiler and launcher, and gets
# every object from the cache. Paths are made relative to the tree and the build directory is not
# hashed (a Release build has no debug information naming it), so both directories share entries.
LAUNCHER := $(if $(shell command -v ccache 2>/dev/null),-DCMAKE_CXX_COMPILER_LAUNCHER=ccache,)
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

SANITIZER_ENV := ASAN_OPTIONS=halt_on_error=1:print_stacktrace=1:detect_leaks=1 \
                 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

.PHONY: all deps configure build test install configure-asan build-asan test-asan demo demo-materials bench clean \
        configure-fuzz build-fuzz fuzz stress configure-tsan build-tsan test-tsan test-wheel-portable \
        bench-peers bench-peers-check

all: build

deps:
	scripts/install-deps

configure:
	cmake -S . -B $(BUILD_DIR) $(call generator_for,$(BUILD_DIR)) -DCMAKE_BUILD_TYPE=Release $(LAUNCHER)

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: deps
	$(MAKE) build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

install: build
	cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# The wheel ctest python.wheel builds and repairs, in a Debian 12 root debootstrapped once into
# $(BUILD_DIR)/fresh-debian-root (kept, with pip's downloads, for the next run).
test-wheel-portable: deps
	$(MAKE) build
	ctest --test-dir $(BUILD_DIR) -R '^python\.wheel$$' --output-on-failure
	tests/python/fresh_debian_root.sh . $(BUILD_DIR)/fresh-debian-root $(BUILD_DIR)-wheel/dist

# Sanitizer and fuzz builds: optimised (apps/ and tests/ at -O1, cmake/Sanitizers.cmake), with
# line tables only (-g1: file and line in every stack trace, at a fraction of full debug
# information's compile time), without the benchmarks.
SANITIZER_FLAGS := -DCMAKE_BUILD_TYPE=RelWithDebInfo '-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG' \
                   -DACDF_BUILD_BENCHMARKS=OFF

configure-asan:
	cmake -S . -B $(ASAN_DIR) $(call generator_for,$(ASAN_DIR)) $(SANITIZER_FLAGS) -DACDF_SANITIZE=address,undefined

build-asan: configure-asan
	cmake --build $(ASAN_DIR) -j $(JOBS)

test-asan: deps
	$(MAKE) build-asan
	$(SANITIZER_ENV) ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS)

# The example scenes' measured materials (scenes/demo.json, product.json, rgl.json), generated once;
# needs $(BUILD_DIR)/bin/acdf.
demo-materials:
	@mkdir -p $(DEMO_DIR)
	@set -e; for m in $(DEMO_BRDFS); do \
	  [ -f $(DEMO_DIR)/$$m.binary ] || $(BUILD_DIR)/bin/acdf merl-gen --nbrdf $$m -o $(DEMO_DIR)/$$m.binary; \
	done
	@[ -f $(DEMO_DIR)/red-plastic.bsdf ] || $(BUILD_DIR)/bin/acdf rgl-gen --preset red-plastic -o $(DEMO_DIR)/red-plastic.bsdf

demo: deps
	$(MAKE) build
	$(MAKE) demo-materials
	$(BUILD_DIR)/bin/acdf render scenes/demo.json -o $(DEMO_DIR)/demo.exr
	$(BUILD_DIR)/bin/acdf render scenes/product.json -o $(DEMO_DIR)/product.exr
	$(BUILD_DIR)/bin/acdf cdf-stats $(DEMO_INPUT)
	@set -e; for m in $(DEMO_BRDFS); do \
	  $(BUILD_DIR)/bin/acdf brdf-stats $(DEMO_DIR)/$$m.binary --samples $(DEMO_BRDF_SAMPLES); \
	done

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
	/usr/bin/python3 bench/report.py --update docs/performance.md --command "make bench" $(RESULTS_DIR)/bench_*.json
	@if ls $(BUILD_DIR)/python/acdf/_acdf*.so >/dev/null 2>&1; then \
	  echo "== bench_python.py -> $(RESULTS_DIR)/python.json"; \
	  /usr/bin/python3 bench/bench_python.py --build $(BUILD_DIR) --json $(RESULTS_DIR)/python.json; \
	fi
	$(MAKE) demo-materials
	/usr/bin/python3 bench/paper_reproduction.py --acdf $(BUILD_DIR)/bin/acdf --materials $(DEMO_DIR) \
	  --update docs/paper-reproduction.md
	$(BENCH_ERROR_COMMAND)
	/usr/bin/python3 bench/error_report.py docs $(BENCH_ERROR_DIR)/results.json docs/performance.md docs/bench-error \
	  --command "$(BENCH_ERROR_COMMAND)"

# make bench-peers: the options of bench/peers/bench_peers.py (its --help), e.g. PEERS_ARGS="scenes/furnace.json
# --seeds 8"; with no scene named, every scene of scenes/ and bench/peers/scenes/ (those a peer cannot express
# are listed with the reason). About 10 minutes on 2 cores with the defaults below.
PEERS_ARGS ?= --seeds 4 --spp 16,64 --resolution 256x192 --threads 2
PEERS_OUT ?= $(RESULTS_DIR)/peers
PEERS_ENV := ACDF_PROGRAM=$(abspath $(BUILD_DIR))/bin/acdf PYTHONPATH=$(abspath $(BUILD_DIR))/python

bench-peers-check: deps
	$(MAKE) build
	scripts/install-peers
	$(PEERS_ENV) .venv-peers/bin/python -m pytest -q -p no:cacheprovider bench/peers

bench-peers: bench-peers-check
	$(PEERS_ENV) .venv-peers/bin/python bench/peers/bench_peers.py $(PEERS_ARGS) --out $(PEERS_OUT)

# Each target runs FUZZ_SECONDS on a working corpus in $(FUZZ_DIR)/corpus/<target>, seeded from
# fuzz/corpus/<target> (read only); a crash is saved under $(FUZZ_DIR)/artifacts/<target>/ and
# fails the run. fuzz/lsan.supp documents the one third-party leak suppressed.
FUZZ_ENV := ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:quarantine_size_mb=64 \
            UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
            LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp

configure-fuzz:
	CC=clang CXX=clang++ cmake -S . -B $(FUZZ_DIR) $(call generator_for,$(FUZZ_DIR)) $(SANITIZER_FLAGS) \
	  -DACDF_FUZZ=ON -DBUILD_TESTING=OFF

build-fuzz: configure-fuzz
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))

fuzz: deps
	$(MAKE) build-fuzz
	@set -e; for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_DIR)/corpus/$$t $(FUZZ_DIR)/artifacts/$$t; \
	  log=$(FUZZ_DIR)/artifacts/$$t/last-run.log; \
	  echo "== fuzz_$$t for $(FUZZ_SECONDS) s"; \
	  if ! $(FUZZ_ENV) $(FUZZ_DIR)/bin/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -seed=$(FUZZ_SEED) -rss_limit_mb=4096 \
	      -print_final_stats=1 -artifact_prefix=$(FUZZ_DIR)/artifacts/$$t/ \
	      $(FUZZ_DIR)/corpus/$$t fuzz/corpus/$$t >$$log 2>&1; then \
	    tail -n 60 $$log; echo "fuzz_$$t FAILED (log: $$log)" >&2; exit 1; \
	  fi; \
	  grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)' $$log; \
	done

stress: deps
	$(MAKE) configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target acdf_stress
	@mkdir -p $(RESULTS_DIR)
	$(BUILD_DIR)/bin/acdf_stress $(STRESS_ARGS)

# Only the multithreaded tests (ctest label "concurrency": the shared-table tests and the renderer's
# in-process tests) are built and run under TSan.
TSAN_TARGETS := test_concurrency test_integrator_furnace test_integrator_consistency test_integrator_determinism
configure-tsan:
	cmake -S . -B $(TSAN_DIR) $(call generator_for,$(TSAN_DIR)) $(SANITIZER_FLAGS) -DACDF_SANITIZE=thread

build-tsan: configure-tsan
	cmake --build $(TSAN_DIR) -j $(JOBS) --target $(TSAN_TARGETS)

test-tsan: deps
	$(MAKE) build-tsan
	TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:suppressions=$(CURDIR)/tests/concurrency/tsan.supp \
	  ctest --test-dir $(TSAN_DIR) -L concurrency --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD_DIR) $(BUILD_DIR)-wheel $(ASAN_DIR) $(FUZZ_DIR) $(TSAN_DIR)

# Partita: `make demo` renders the default scene end to end, `make test` builds and runs every
# test. Both install missing Debian packages first (scripts/packages.txt; quick when present).
BUILD      ?= build
BENCH_BUILD ?= build-bench
FUZZ_BUILD ?= build-fuzz
JOBS       ?= $(shell nproc)
CMAKE_ARGS ?=
SCENE      ?= scenes/cornell/cornell.gltf
DEMO_SPP   ?= 64

# ccache keys on relative paths under the checkout, so a fresh clone elsewhere (CI) still hits.
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

.PHONY: all deps configure build test demo bench references fuzz format scenes clean

all: build

deps:
	@./scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 900

# Renders through the daemon: with no --server, `partita` starts a private partitad on a free
# loopback port with a temporary store for the duration of the command.
demo: build
	@mkdir -p out
	$(BUILD)/client/partita render $(SCENE) --spp $(DEMO_SPP) --out out/demo.exr --previews out/previews
	@echo "demo: out/demo.exr (radiance, one layer per path type), out/demo.png, out/demo.json, out/previews/"

bench: deps
	@cmake -S . -B $(BENCH_BUILD) -DCMAKE_BUILD_TYPE=Release -DPARTITA_BUILD_TESTS=OFF -DPARTITA_BUILD_BENCH=ON \
	  -DPARTITA_BUILD_SERVICE=ON >/dev/null
	@cmake --build $(BENCH_BUILD) -j$(JOBS)
	$(BENCH_BUILD)/bench/partita-eval throughput --scene $(SCENE) --json $(BENCH_BUILD)/throughput.json
	$(BENCH_BUILD)/bench/partita-eval service --json $(BENCH_BUILD)/service.json
	$(BENCH_BUILD)/bench/partita-bench --benchmark_min_time=0.2

# The cached reference of every shipped scene (bench/make-references.sh; SPP, WIDTH, HEIGHT from
# the environment). REFERENCE_ARGS="--force" re-renders them, "--algorithm pt" until bdpt exists.
REFERENCE_ARGS ?=
references: deps
	@cmake -S . -B $(BENCH_BUILD) -DCMAKE_BUILD_TYPE=Release -DPARTITA_BUILD_BENCH=ON >/dev/null
	@cmake --build $(BENCH_BUILD) -j$(JOBS) --target partita-eval
	PARTITA_EVAL=$(BENCH_BUILD)/bench/partita-eval bench/make-references.sh $(REFERENCE_ARGS)

fuzz: deps
	@cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DPARTITA_BUILD_TESTS=OFF -DPARTITA_BUILD_FUZZ=ON >/dev/null
	@cmake --build $(FUZZ_BUILD) -j$(JOBS) --target fuzz_gltf_loader
	@mkdir -p fuzz-findings
	$(FUZZ_BUILD)/tests/fuzz/fuzz_gltf_loader -max_total_time=$${FUZZ_SECONDS:-120} -artifact_prefix=fuzz-findings/ \
	  fuzz-findings scenes

scenes:
	/usr/bin/python3 scenes/generate.py

format:
	@find core tools tests bench server client -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(BENCH_BUILD) $(FUZZ_BUILD) out

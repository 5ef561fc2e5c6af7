# Partita: `make demo` renders the default scene end to end, `make test` builds and runs every
# test. Both install missing Debian packages first (scripts/packages.txt; quick when present).
BUILD      ?= build
BENCH_BUILD ?= build-bench
ASAN_BUILD ?= build-asan
FUZZ_BUILD ?= $(ASAN_BUILD)
TSAN_BUILD ?= build-tsan
JOBS       ?= $(shell nproc)
CMAKE_ARGS ?=
SCENE      ?= scenes/cornell/cornell.gltf
DEMO_SPP   ?= 64

# ccache keys on relative paths under the checkout, so a fresh clone elsewhere (CI) still hits.
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

.PHONY: all deps configure build test test-asan test-tsan demo bench references fuzz format scenes clean

all: build

deps:
	@./scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 900

# Sanitizer builds of the tests (.ci/run runs both after `make test`). Each reports into
# <build>/sanitizer-logs, the daemons and tools the service tests start included, and fails on
# any report (scripts/sanitized-ctest.sh; suppressions in tests/sanitizers/).
# Left out under both, as too slow there and not about memory or threads: the statistical
# tests that render until an estimate converges to a reference or a bias shows (Converge,
# AgreesWith, Chi2, ShowsAsBias, EstimatesTheIntegral),
# the tests that a time budget or a cancel ends within a wall-clock bound (TimeBudget,
# WithinASecond: code 4-10x slower misses the bound by design), the end-to-end CLI runs of
# partita-local (LocalCli) and the client tests (label client).
# -O1: what the sanitizers recommend, and much quicker to compile than -O3 on 2 cores.
SAN_RELEASE := -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" -DCMAKE_CXX_COMPILER=clang++
# One clang build folder for the ASan tests and the fuzz targets (make fuzz): the same options.
ASAN_CMAKE := $(SAN_RELEASE) -DPARTITA_SANITIZE=ON -DPARTITA_BUILD_FUZZ=ON
SAN_SLOW := Converge|AgreesWith|Chi2|ShowsAsBias|EstimatesTheIntegral|LocalCli|TimeBudget|WithinASecond|_NOT_BUILT
# Left out under ASan: the service tests whose renders outlast their gRPC deadlines 10-20x
# slower (ServiceMlt's 2048 mutations a pixel, every algorithm of ServiceParameters, the Slurm
# cluster's shards), and the tests that compare the daemon's peak memory with its estimate
# (PeakRss, WithinItsEstimate, PiecesNotTheirSize, ItsReceiveQuota: ASan's shadow memory and
# quarantine add to the peak, by design: its quarantine alone keeps 256 MiB of freed upload
# pieces).
ASAN_SERVICE_SLOW := PeakRss|WithinItsEstimate|PiecesNotTheirSize|ItsReceiveQuota|ServiceMlt.JobHasBootstrap|ServiceParameters|ServiceSlurm
# ASan + UBSan: the unit and service tests.
test-asan: deps
	@cmake -S . -B $(ASAN_BUILD) $(ASAN_CMAKE) >/dev/null
	@cmake --build $(ASAN_BUILD) -j$(JOBS) --target partita-tests partita-server-tests partita-service-tests
	@scripts/sanitized-ctest.sh $(ASAN_BUILD) -j$(JOBS) --timeout 900 -LE client \
	  -E '$(SAN_SLOW)|$(ASAN_SERVICE_SLOW)'
# TSan: the tests whose work runs on several threads in the core: the thread pool, every
# algorithm's chains or tiles on a pool (EveryAlgorithm), sharded renders and thread counts,
# progress, films splatted from several threads; and the job system in one process (client
# threads submitting, watching, cancelling and deleting while the runners render:
# tests/server). (TSan is 5-15x slower: the rest of the suite runs under ASan.) Not the service
# tests: Debian's gRPC, abseil and protobuf are not instrumented, and their hand-offs showed as
# thousands of races in grpcpp's inlined callback code; a suppression of libgrpc would hide
# every race in our callbacks as well.
TSAN_UNIT := ^ThreadPool\.|EveryAlgorithm|ShardedRender|ThreadCount|ProgressReporter|^Film\.|^JobManagerThreads\.
test-tsan: deps
	@cmake -S . -B $(TSAN_BUILD) $(SAN_RELEASE) -DPARTITA_TSAN=ON >/dev/null
	@cmake --build $(TSAN_BUILD) -j$(JOBS) --target partita-tests partita-server-tests
	@scripts/sanitized-ctest.sh $(TSAN_BUILD) -j$(JOBS) --timeout 900 -LE client \
	  -R '$(TSAN_UNIT)' -E '$(SAN_SLOW)'

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

# Every libFuzzer target (tests/fuzz/README.md) for FUZZ_SECONDS each, from its seeds in
# tests/fuzz/seeds/<target>; the corpus grows in fuzz-corpus/<target>, findings land in
# fuzz-findings/. FUZZ_TARGETS picks some.
FUZZ_TARGETS ?= gltf_loader environment_image shard_files chain_plan job_store_rows job_spec upload_stream
FUZZ_SECONDS ?= 120
fuzz: deps
	@cmake -S . -B $(FUZZ_BUILD) $(ASAN_CMAKE) >/dev/null
	@cmake --build $(FUZZ_BUILD) -j$(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@mkdir -p fuzz-findings
	@set -e; for t in $(FUZZ_TARGETS); do \
	  mkdir -p fuzz-corpus/$$t; \
	  echo "fuzz_$$t: $(FUZZ_SECONDS) s (log: fuzz-findings/$$t.log)"; \
	  if ! $(FUZZ_BUILD)/tests/fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
	    -print_final_stats=1 -artifact_prefix=fuzz-findings/$$t- \
	    $$(test -f tests/fuzz/$$t.dict && echo -dict=tests/fuzz/$$t.dict) \
	    fuzz-corpus/$$t tests/fuzz/seeds/$$t >fuzz-findings/$$t.log 2>&1; then \
	    tail -n 60 fuzz-findings/$$t.log; exit 1; \
	  fi; \
	  grep -E '^stat::(number_of_executed_units|peak_rss_mb)|DONE' fuzz-findings/$$t.log; \
	done

scenes:
	/usr/bin/python3 scenes/generate.py

format:
	@find core tools tests bench server client -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(BENCH_BUILD) $(ASAN_BUILD) $(TSAN_BUILD) out

# liftcheck: two commands on a fresh Debian machine.
#   make validate   install missing packages, build, run every scenario on every engine, write the report
#   make test       install missing packages, build, run the test suite (ctest)
#   make sanitize   AddressSanitizer + UndefinedBehaviorSanitizer build (build-sanitize): unit tests and a short validate
#   make format     apply .clang-format to the C++ sources (the ctest `format` checks them)
#   make fuzz       libFuzzer targets (clang, build-fuzz) over --set, results files and traces, FUZZ_TIME seconds each

PACKAGES := cmake g++ make pkg-config git python3 \
            libeigen3-dev libboost-dev nlohmann-json3-dev libcli11-dev libfmt-dev libgtest-dev \
            libbullet-dev libode-dev libosmesa6-dev libpng-dev libimagequant-dev libstb-dev fonts-dejavu-core gnuplot-nox \
            libbenchmark-dev libmujoco-dev libqhull-dev libdart-dev libdart-external-ikfast-dev libsimbody-dev libxml2-utils \
            libmd4c-dev libmd4c-html0-dev libsimdjson-dev clang-format
# Node and npm run the outside engines (engines/outside): Debian's packages, unless a node with its
# npm is installed already (NodeSource's nodejs bundles npm and conflicts with Debian's npm).
NODE_PACKAGES := nodejs npm
BUILD_DIR ?= build
REPORT_DIR ?= $(BUILD_DIR)/report
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
SANITIZE_DIR ?= build-sanitize
FUZZ_DIR ?= build-fuzz
FUZZ_TIME ?= 60
FUZZ_PACKAGES := clang libclang-rt-14-dev
# Sanitizers stop at the first finding; third-party leaks are suppressed, each with its reason, in
# tests/sanitize/*.supp.
SANITIZE_ENV := ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1 \
                UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=$(CURDIR)/tests/sanitize/ubsan.supp \
                LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitize/lsan.supp:print_suppressions=0

OUTSIDE_DIR := engines/outside
# The outside engines' npm packages, exactly as package-lock.json pins them (npm writes this file
# into node_modules at the end of every install; it is redone when the lock file changes).
NODE_STAMP := $(OUTSIDE_DIR)/node_modules/.package-lock.json

.PHONY: all deps install-packages configure build validate test report-check bench clean sanitize fuzz npm-deps format tune-table readme

all: build

deps:
	@$(MAKE) --no-print-directory install-packages PKGS="$(PACKAGES) $$(command -v node >/dev/null && command -v npm >/dev/null || echo '$(NODE_PACKAGES)')"

# Installs the Debian packages in PKGS that are missing (as root), or prints the apt-get line.
install-packages:
	@missing=""; \
	for p in $(PKGS); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; \
	  else \
	    echo "liftcheck needs these Debian packages; run:"; \
	    echo "  sudo apt-get install -y$$missing"; \
	    exit 1; \
	  fi; \
	fi

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release >/dev/null

build: configure npm-deps
	@cmake --build $(BUILD_DIR) -j $(JOBS)

npm-deps: deps $(NODE_STAMP)

$(NODE_STAMP): $(OUTSIDE_DIR)/package-lock.json $(OUTSIDE_DIR)/package.json
	cd $(OUTSIDE_DIR) && npm ci --no-audit --no-fund --loglevel=error
	@touch $@

validate: build
	./$(BUILD_DIR)/liftcheck validate --out $(REPORT_DIR) --baseline data/baselines/default.json

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

# Reads the first screen of the report of `make validate` in headless Chromium at 1366x768 (element
# sizes from the DOM): the whole matrix and the counts fit, each cell shows its headline metric.
report-check:
	@$(MAKE) --no-print-directory install-packages PKGS="chromium python3"
	@test -f $(REPORT_DIR)/index.html || $(MAKE) --no-print-directory validate
	python3 tests/screenshot_check.py $(REPORT_DIR) $(BUILD_DIR)/report-screenshot.png

# The unit tests and a short validate under ASan and UBSan (the slow conformance and fault suites
# are left to `make test`). -O1 -g1: line numbers in reports at half the compile time of -O2 -g.
sanitize: deps
	@cmake -S . -B $(SANITIZE_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DLIFTCHECK_SANITIZE=ON >/dev/null
	@cmake --build $(SANITIZE_DIR) -j $(JOBS) --target liftcheck test_input test_harness test_report test_models
	$(SANITIZE_ENV) ctest --test-dir $(SANITIZE_DIR) --output-on-failure -j $(JOBS) -LE 'validate|faults' -E 'NOT_BUILT|^report$$|^reliability$$'
	rm -rf $(SANITIZE_DIR)/report
	$(SANITIZE_ENV) ./$(SANITIZE_DIR)/liftcheck validate --filter 'car.circle,disks.linear' --engines analytic,ode,bullet --no-sweeps --out $(SANITIZE_DIR)/report

# libFuzzer over the input code (no engine linked), FUZZ_TIME seconds per target, from the seed
# corpus in tests/fuzz/corpus/ (new inputs go to $(FUZZ_DIR)/corpus/, crashes to $(FUZZ_DIR)/).
fuzz: deps
	@$(MAKE) --no-print-directory install-packages PKGS="$(FUZZ_PACKAGES)"
	@cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIFTCHECK_FUZZ=ON -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null
	@cmake --build $(FUZZ_DIR) -j $(JOBS) --target fuzz_set fuzz_results fuzz_trace
	@for t in set results trace; do \
	  mkdir -p $(FUZZ_DIR)/corpus/$$t; \
	  echo "fuzz_$$t: $(FUZZ_TIME) s"; \
	  ./$(FUZZ_DIR)/tests/fuzz/fuzz_$$t -max_total_time=$(FUZZ_TIME) -max_len=4096 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
	    -artifact_prefix=$(FUZZ_DIR)/fuzz_$$t- $(FUZZ_DIR)/corpus/$$t tests/fuzz/corpus/$$t 2>$(FUZZ_DIR)/fuzz_$$t.log \
	    || { tail -40 $(FUZZ_DIR)/fuzz_$$t.log; exit 1; }; \
	  grep -E '^stat::number_of_executed_units|^Done' $(FUZZ_DIR)/fuzz_$$t.log; \
	done

format:
	@$(MAKE) --no-print-directory install-packages PKGS="clang-format"
	find models engines scenarios harness reports cli input tests bench examples -path '*/node_modules' -prune -o \
	  \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print | xargs clang-format --style=file -i

# Every benchmark (analytic models, car steps per engine against its raw loop, rendering); the
# results also go to $(BUILD_DIR)/bench.json.
# liftcheck tune's answers for every configuration on the headline scenarios, written to
# data/tune/table.json (about 20 minutes on 2 cores; the ctest tune_table says when it is stale).
tune-table: build
	python3 tests/tools/tune_table.py --liftcheck $(BUILD_DIR)/liftcheck --budget 16 --jobs $(JOBS)

# What the README shows, from the current build: the run block, the suite's counts (from the
# committed baseline), the tune figure and the screenshot of the report's first screen (of
# `make validate`'s report); `ctest -R readme` fails when the block or the counts differ.
readme: build report-check
	python3 tests/readme_check.py $(BUILD_DIR)/liftcheck README.md data/baselines/default.json --write
	cp $(BUILD_DIR)/report-screenshot.png docs/report.png

bench: build
	./$(BUILD_DIR)/liftcheck_bench --benchmark_out=$(BUILD_DIR)/bench.json --benchmark_out_format=json

clean:
	rm -rf $(BUILD_DIR) $(SANITIZE_DIR) $(FUZZ_DIR)

# liftcheck: two commands on a fresh Debian machine.
#   make validate   install missing packages, build, run every scenario on every engine, write the report
#   make test       install missing packages, build, run the test suite (ctest)

PACKAGES := cmake g++ make pkg-config git python3 \
            libeigen3-dev libboost-dev nlohmann-json3-dev libcli11-dev libfmt-dev libgtest-dev \
            libbullet-dev libode-dev libosmesa6-dev libpng-dev libstb-dev fonts-dejavu-core gnuplot-nox \
            libbenchmark-dev libmujoco-dev libqhull-dev libdart-dev libdart-external-ikfast-dev libxml2-utils
BUILD_DIR ?= build
REPORT_DIR ?= $(BUILD_DIR)/report
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all deps install-packages configure build validate test report-check bench clean

all: build

deps:
	@$(MAKE) --no-print-directory install-packages PKGS="$(PACKAGES)"

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

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

validate: build
	./$(BUILD_DIR)/liftcheck validate --out $(REPORT_DIR) --baseline reports/baselines/default.json

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

# Opens the report of `make validate` in headless Chromium; the screenshot must show the summary matrix.
report-check:
	@$(MAKE) --no-print-directory install-packages PKGS="chromium python3"
	@test -f $(REPORT_DIR)/index.html || $(MAKE) --no-print-directory validate
	python3 tests/screenshot_check.py $(REPORT_DIR) $(REPORT_DIR)/screenshot.png

# Every benchmark (analytic models, car steps per engine against its raw loop, rendering); the
# results also go to $(BUILD_DIR)/bench.json.
bench: build
	./$(BUILD_DIR)/liftcheck_bench --benchmark_out=$(BUILD_DIR)/bench.json --benchmark_out_format=json

clean:
	rm -rf $(BUILD_DIR)

# grainlab: `make run` and `make test` go from a fresh Debian 12 clone to a result.
BUILD  ?= build
CONFIG ?= configs/quick.yaml
# Each `make run` writes a new run directory (grainlab never overwrites a run); runs/latest points to it.
RUN_DIR ?= runs/$(basename $(notdir $(CONFIG)))-$(shell date +%Y%m%d-%H%M%S)
JOBS   ?= $(shell nproc)
CMAKE_ARGS ?=

.PHONY: all setup configure build run test clean distclean

all: build

setup:
	@scripts/setup-deps.sh >/dev/null

$(BUILD)/CMakeCache.txt:
	@prefix=$$(scripts/setup-deps.sh) && \
	  cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DKokkos_ROOT="$$prefix" $(CMAKE_ARGS)

configure: setup $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

run: build
	$(BUILD)/grainlab run $(CONFIG) --out $(RUN_DIR)
	$(BUILD)/grainlab plot $(RUN_DIR)
	@ln -sfn $(notdir $(RUN_DIR)) runs/latest && echo "runs/latest -> $(RUN_DIR) (figures in $(RUN_DIR)/figures)"

# Tests declare their own thread counts (OMP_NUM_THREADS per test, see tests/CMakeLists.txt);
# --parallel lets CTest pack them onto the cores using each test's PROCESSORS property.
test: build
	cd $(BUILD) && ctest --output-on-failure --parallel $(JOBS)

clean:
	cmake --build $(BUILD) --target clean

distclean:
	rm -rf $(BUILD)

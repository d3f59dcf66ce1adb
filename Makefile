# Thin front to CMake/CTest. Every target installs missing Debian packages first.
JOBS      ?= 2
BUILD     ?= build
ASAN      ?= build-asan
FUZZ      ?= build-fuzz
# seconds each fuzz target runs in `make fuzz`
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?= config set positions xyz gsd table checkpoint
CMAKE_ARGS ?=

.PHONY: all deps build asan demo check docs bench validate fuzz format clean

all: build

deps:
	@scripts/install-deps

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DHSBD_WERROR=ON $(CMAKE_ARGS) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

asan: deps
	@cmake -S . -B $(ASAN) -DCMAKE_BUILD_TYPE=Debug -DHSBD_WERROR=ON -DHSBD_SANITIZE=ON $(CMAKE_ARGS) >/dev/null
	@cmake --build $(ASAN) -j $(JOBS)

# The flagship examples: hard rods in a cosine potential against Percus' exact profile,
# and a hard-sphere fluid (g(r) against Carnahan-Starling, MSD, F_s); both plotted.
demo: build
	@rm -rf runs/demo
	@$(BUILD)/hsbd run examples/rods-cosine.ini --quiet --out runs/demo/rods
	@$(BUILD)/hsbd theory percus --sigma 0.5 --rho 0.5 --amplitude 6 --out runs/demo/rods/percus.tsv
	@/usr/bin/python3 tools/plot_rods.py runs/demo/rods --theory runs/demo/rods/percus.tsv >/dev/null
	@$(BUILD)/hsbd run examples/spheres-fluid.ini --quiet --out runs/demo/spheres
	@/usr/bin/python3 tools/plot_spheres.py runs/demo/spheres >/dev/null
	@echo "rods (density, contact density, MSD): runs/demo/rods/plot.png"
	@echo "spheres (g(r), MSD, F_s):              runs/demo/spheres/plot.png"

# Whole test suite: optimised build (all tests) and AddressSanitizer+UBSan build (all tests).
check: build asan
	@ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)
	@ctest --test-dir $(ASAN) --output-on-failure -j $(JOBS)

# The documentation site (Sphinx with MyST, Debian's packages) from docs/ into
# $(BUILD)/docs/html; the Python API page imports the module of $(BUILD)/python. Any
# warning or broken internal link fails it, as it fails test_docs in make check.
docs: build
	@HSBD_PYTHONPATH=$(abspath $(BUILD))/python /usr/bin/python3 -m sphinx -W -n -E --keep-going -q -b html \
	    -d $(BUILD)/docs/.doctrees docs $(BUILD)/docs/html
	@echo "documentation: $(BUILD)/docs/html/index.html"

bench: build
	@bench/run $(BUILD)/hsbd

# Long statistical validation runs (tighter error bars), then simulations against the
# exact theory with their figures; see README and docs/validation.md.
validate: build
	@HSBD_VALIDATE=long ctest --test-dir $(BUILD) -L physics --output-on-failure -j $(JOBS)
	@$(BUILD)/hsbd validate --out runs/validate --jobs $(JOBS); rc=$$?; \
	 /usr/bin/python3 tools/plot_validation.py runs/validate; \
	 /usr/bin/python3 tools/plot_driven.py $(BUILD)/hsbd runs/validate/driven || rc=1; \
	 tools/walls_dt_scan.sh $(BUILD)/hsbd || rc=1; \
	 tools/validate_mips.sh $(BUILD)/hsbd runs/validate/mips || rc=1; exit $$rc

# libFuzzer on each harness of tests/fuzz/ in turn for FUZZ_SECONDS (clang, installed on
# demand); new inputs go to $(FUZZ)/corpus/, findings to $(FUZZ)/findings/ (README, fuzzing).
fuzz:
	@HSBD_FUZZ=1 scripts/install-deps
	@cmake -S . -B $(FUZZ) -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=Debug -DHSBD_WERROR=ON -DHSBD_FUZZ=ON $(CMAKE_ARGS) >/dev/null
	@cmake --build $(FUZZ) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@scripts/fuzz $(FUZZ) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

format:
	@clang-format -i $$(git ls-files '*.c' '*.h')

clean:
	@rm -rf $(BUILD) $(ASAN) $(FUZZ)

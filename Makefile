# fovea — the two set-up commands: `make run` and `make test`. Both install missing Debian packages first.
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
ARGS ?=
CMAKE_FLAGS ?=

.PHONY: run test check deps release debug asan clean format

deps:
	@tools/install-deps.sh

build/release/CMakeCache.txt: | deps
	cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DFV_WERROR=ON $(CMAKE_FLAGS) >/dev/null

build/debug/CMakeCache.txt: | deps
	cmake -S . -B build/debug -DCMAKE_BUILD_TYPE=Debug -DFV_WERROR=ON $(CMAKE_FLAGS) >/dev/null

# The sanitizer build uses clang so that it can also build the libFuzzer targets.
build/asan/CMakeCache.txt: | deps
	CC=clang cmake -S . -B build/asan -DCMAKE_BUILD_TYPE=Debug -DFV_SANITIZE=ON -DFV_WERROR=ON $(CMAKE_FLAGS) >/dev/null

release: deps build/release/CMakeCache.txt
	cmake --build build/release -j $(JOBS)

debug: deps build/debug/CMakeCache.txt
	cmake --build build/debug -j $(JOBS)

asan: deps build/asan/CMakeCache.txt
	cmake --build build/asan -j $(JOBS)

# Renders the built-in Cornell box headless (stereo, side by side) into out/ and prints the summary: 8 frames, the last
# saved (out/frame_00007.png), so that the picture has the temporal history a viewer's frame has.
run: release
	build/release/tools/fovea/fovea run --out out --frames 8 $(ARGS)

# Pure, sim and fuzz tests under ASan+UBSan; GPU and command-line tests on the release build (lavapipe + validation).
test: release asan
	cd build/asan && ctest --output-on-failure -j $(JOBS) -L 'unit|sim|fuzz|extreme' $(ARGS)
	cd build/release && CI=$${CI:-true} ctest --output-on-failure -j $(JOBS) -L 'gpu|cli' $(ARGS)

# The edit loop's tier: the pure and sim tests under ASan+UBSan (no GPU, no CLI renders), about two minutes.
check: asan
	cd build/asan && ctest --output-on-failure -j $(JOBS) -L 'unit|sim' $(ARGS)

clean:
	rm -rf build out

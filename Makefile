# Thin wrapper over CMake: `make demo`, `make test` are all a newcomer needs.
BUILD      ?= build
ASAN_BUILD ?= build-asan
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all build demo install test test-release test-asan bench fuzz clean web web-serve web-for-tests

all: build

build:
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DEW_WEB_DIR=$(abspath $(WEB_BUILD))/web >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

# Installs the command, the headers, libedgewise.a and libedgewise.so,
# edgewise.pc, the man page and the bash completion under PREFIX
# (docs/library.md); DESTDIR=... stages it for packaging.
PREFIX ?= /usr/local
install:
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=$(PREFIX) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)
	cmake --install $(BUILD) --prefix $(PREFIX)

# Renders the built-in scene (no files from outside the repository) to
# demo.png.  Builds the command alone (and the library it links), not the
# tests and labs: the first picture comes a build of the library after a clone.
demo:
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD) -j $(JOBS) --target edgewise_cli
	./$(BUILD)/edgewise demo --out demo.png --stats

# The standard benchmark (docs/performance.md): the maps of BENCHMARK.md at three
# sizes, one thread and all cores.  Written to a temporary file first so an
# interrupted run leaves the previous LATEST.jsonl intact.
EW_DATA     ?= ../shared/data/librequake
BENCH_MAPS  ?= e1m1 lqdm7 e4m1 start
BENCH_SIZES ?= 640x480 1920x1080 3840x2160
bench: build
	@mkdir -p bench/results
	./$(BUILD)/edgewise bench $(BENCH_MAPS) --data $(EW_DATA) $(addprefix --size ,$(BENCH_SIZES)) \
		--threads 1 --threads 0 --table --out bench/results/LATEST.jsonl.tmp
	@mv bench/results/LATEST.jsonl.tmp bench/results/LATEST.jsonl
	@echo "wrote bench/results/LATEST.jsonl"

# Fuzzing (clang + libFuzzer, fuzz/run.sh): builds build-fuzz/ and runs every
# target FUZZ_SECONDS seconds, then one summary line per target.
FUZZ_SECONDS ?= 60
fuzz:
	FUZZ_SECONDS=$(FUZZ_SECONDS) ./fuzz/run.sh

# The web page (docs/web.md): the library and app/web/ compiled to
# WebAssembly by Debian's emscripten into $(WEB_BUILD)/web (edgewise.wasm and
# its JavaScript, with threads and without, index.html, page.js, serve.mjs).
# emcc runs its JavaScript optimizer under node with Debian's acorn module,
# found through NODE_PATH.  web-serve serves it on localhost with the
# cross-origin isolation headers (threads), EW_DATA under /data/: open
# http://127.0.0.1:$(WEB_PORT)/ or ...?map=data/maps/lqdm7.bsp&color=true.
WEB_BUILD ?= build-web
WEB_PORT  ?= 8080
WEB_ENV    = NODE_PATH=$${NODE_PATH:+$$NODE_PATH:}/usr/share/nodejs
web:
	@command -v emcc >/dev/null 2>&1 || { echo "make web: emcc not found (apt-get install emscripten)" >&2; exit 1; }
	@$(WEB_ENV) emcmake cmake -S . -B $(WEB_BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@$(WEB_ENV) cmake --build $(WEB_BUILD) -j $(JOBS)
	@echo "make web: the page is in $(WEB_BUILD)/web (make web-serve serves it)"

web-serve: web
	node $(WEB_BUILD)/web/serve.mjs --root $(WEB_BUILD)/web --port $(WEB_PORT) --mount /data=$(EW_DATA)

# make test builds the page first where emscripten is installed (test_web
# opens it in chromium; without emcc that test is skipped, which CI=true
# does not allow: .ci/run installs it).
web-for-tests:
	@if command -v emcc >/dev/null 2>&1; then $(MAKE) --no-print-directory web; \
	else echo "make test: emcc not found, the web page is not built (test_web will be skipped)"; fi

# Every test, in the release build and again under ASan + UBSan + LeakSanitizer
# (a leak, an invalid access or any undefined behaviour fails the test).
test: test-release test-asan

# Each run's output is kept in BUILD/ctest.log; with CI=true (.ci/run) a
# skipped test (exit 77: a missing tool or ../shared) fails the run too
# (.ci/no-skips), since CI has everything installed.
test-release: build web-for-tests
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -O ctest.log
	$(if $(filter true,$(CI)),.ci/no-skips $(BUILD)/ctest.log)

test-asan: web-for-tests
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DEW_SANITIZE=ON -DEW_WEB_DIR=$(abspath $(WEB_BUILD))/web >/dev/null
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 \
		UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j $(JOBS) -O ctest.log
	$(if $(filter true,$(CI)),.ci/no-skips $(ASAN_BUILD)/ctest.log)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(WEB_BUILD) build-fuzz demo.png

# vk-render: `make render` renders the figures into out/, `make test` runs every test.
# Both first install the Debian packages they need (see "The two commands" in the README).

# Debian packages, by what needs them.
RUNTIME_PACKAGES := mesa-vulkan-drivers libvulkan1 glmark2-data
# The preview's window: winit opens these X11 libraries at run time.
PREVIEW_PACKAGES := libx11-6 libx11-xcb1 libxcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon0 libxkbcommon-x11-0
# The shaderc crate's build compiles C++; build.rs finds the glslang and SPIRV-Tools archives with pkg-config.
# build.rs translates the browser's shaders with spirv-cross and checks them with glslang-tools' glslangValidator.
BUILD_PACKAGES := libshaderc-dev glslang-dev spirv-tools glslc g++ pkg-config spirv-cross glslang-tools
TEST_PACKAGES := vulkan-validationlayers xvfb xauth chromium chromium-driver curl

CARGO ?= cargo
BIN := $(or $(CARGO_TARGET_DIR),target)/release/vk-render
OUT ?= out

.PHONY: all setup setup-test build render test test-suite test-long test-python wheel test-current bench bench-sampling bench-fit bench-serve bench-peer bench-python bless clean

all: render

## setup: install the packages to build and run vk-render (apt-get; quiet when all are present), after making
## /dev/null the null device where a container left it a regular file (cargo reads it: scripts/repair-dev-null.sh)
setup:
	@scripts/repair-dev-null.sh
	@scripts/install-packages.sh $(RUNTIME_PACKAGES) $(PREVIEW_PACKAGES) $(BUILD_PACKAGES)
	@command -v $(CARGO) >/dev/null || { echo "cargo is missing: install Rust from https://rustup.rs" >&2; exit 1; }
	@scripts/install-wasm-target.sh

## setup-test: also the Khronos validation layer, which every rendering test turns on
setup-test: setup
	@scripts/install-packages.sh $(TEST_PACKAGES)

## build: the release binary
build: setup
	$(CARGO) build --release --locked

## render: every figure of the practical into out/ (each image, and one contact sheet per figure)
render: build
	$(BIN) figures -o $(OUT)

## test: the library's API reference (cargo doc, every warning an error: a public item without docs or a
## broken link fails), the benchmarks built and the build without the preview checked, so that none can rot
## (`cargo check`: the compiler without its code generation, 20 s where the build took 71); then every test
## (unit, shader compilation, GPU renders with validation, CLI errors) and the Python package's tests against
## its wheel, the test binaries and pytest side by side, as many as there are cores (scripts/run-tests.sh;
## `cargo test --release` runs the same Rust tests one binary at a time)
test: setup-test
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --release --locked --no-deps --lib
	$(CARGO) bench --locked --no-run
	$(CARGO) check --release --locked --no-default-features
	$(TEST_SUITE)

## test-suite: make test's tests without its compile-only checks (the API reference, the benchmarks, the
## build without the preview), which read the same sources on any stack: what the Debian 13 stage runs
TEST_SUITE = CARGO="$(CARGO)" VK_RENDER_TEST_PYTHON=1 VK_RENDER_WHEEL="$(VK_RENDER_WHEEL)" \
	scripts/run-tests.sh --release --locked
test-suite: setup-test
	$(TEST_SUITE)

## test-long: the long tests, which CI runs after `make test` (scripts/run-tests.sh --long: the tests marked
## #[ignore = "long: ..."]): the samplers' chi-square over each model's whole range at every view, every
## catalogue scene drawn in the browser against `vk-render render`, the site's check page on every figure,
## the exact mode under the studio and from measured tables' samplers
test-long: setup-test
	CARGO="$(CARGO)" scripts/run-tests.sh --long --release --locked

## test-python: the Python package's tests: its wheel (make wheel, or the one VK_RENDER_WHEEL names) installed
## into a venv made once (scripts/python-env.sh: target/python-venv, with pytest, Dask and matplotlib pinned),
## then pytest with no cargo on PATH (scripts/test-python.sh)
test-python: setup-test
	$(CARGO) build --release --locked
	VK_RENDER_WHEEL="$(VK_RENDER_WHEEL)" scripts/test-python.sh

## wheel: the Python package as a wheel, target/wheels/vk_render-*.whl (maturin; abi3, one wheel for CPython
## 3.9 on; the manylinux tag its symbols allow, checked by auditwheel), which pip installs without Rust
wheel: setup
	@scripts/build-wheel.sh >/dev/null

## test-current: `make test-suite` in a Debian 13 root (Mesa 25 lavapipe, validation layer 1.4), made once
## from Debian's packages and cached (scripts/stage-current.sh; needs root or sudo), built there with the
## README's own steps; its Python tests run against the wheel built here (on Debian 12 in CI), installed
## there without cargo on PATH
WHEELS := $(abspath $(or $(CARGO_TARGET_DIR),target))/wheels
test-current: wheel
	scripts/stage-current.sh test-suite VK_RENDER_WHEEL="$$(ls $(WHEELS)/vk_render-*.whl)"

## bench: the renderer's benchmark (median of 9 runs each); `scripts/stage-current.sh bench` on Debian 13
bench: setup
	$(CARGO) bench --locked --bench render

## bench-sampling: exact images of .brdf spheres under the sky with the files' own samplers and without, side
## by side in one run: the passes and the time to one level (docs/performance.md)
bench-sampling: setup
	$(CARGO) bench --locked --bench sampling

## bench-fit: a four-parameter .brdf fit against the course's Cook-Torrance fit of one measured material, in
## one run (mark: at most twice as long)
bench-fit: setup
	$(CARGO) bench --locked --bench fit

## bench-serve: `vk-render serve` under load in one run: the explore page's frames, a check through the API
## against `vk-render check`, 50 clients for a minute, the page drawing in headless Chromium (first frame,
## frames a second), 500 simulated explorers for a minute (benches/serve.rs)
bench-serve: setup-test
	$(CARGO) bench --locked --bench serve

## bench-peer: vk-render against pyrender (OpenGL on the same Mesa) on the same scenes, in one run, as ratios
## (scripts/bench-pyrender.sh; `scripts/stage-current.sh bench-peer` on Debian 13)
bench-peer: setup
	scripts/bench-pyrender.sh

## bench-python: the Python package against the command line (scripts/bench-python.sh), as ratios
bench-python: setup
	scripts/bench-python.sh

## bless: rewrite the golden images of tests/golden/ from lavapipe's renders (on purpose: review the diff)
bless: setup-test
	$(CARGO) run --release --locked --example bless

clean:
	$(CARGO) clean
	rm -rf $(OUT)

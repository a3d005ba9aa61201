# vk-render: `make render` renders the figures into out/, `make test` runs every test.
# Both first install the Debian packages they need (see BUILD_NOTES in the README).

# Debian packages, by what needs them.
RUNTIME_PACKAGES := mesa-vulkan-drivers libvulkan1 glmark2-data
# The preview's window: winit opens these X11 libraries at run time.
PREVIEW_PACKAGES := libx11-6 libx11-xcb1 libxcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon0 libxkbcommon-x11-0
BUILD_PACKAGES := libshaderc-dev glslang-dev spirv-tools
TEST_PACKAGES := vulkan-validationlayers xvfb xauth

CARGO ?= cargo
BIN := target/release/vk-render
OUT ?= out

.PHONY: all setup setup-test build render test bless clean

all: render

## setup: install the packages to build and run vk-render (apt-get; quiet when all are present)
setup:
	@scripts/install-packages.sh $(RUNTIME_PACKAGES) $(PREVIEW_PACKAGES) $(BUILD_PACKAGES)
	@command -v $(CARGO) >/dev/null || { echo "cargo is missing: install Rust from https://rustup.rs" >&2; exit 1; }

## setup-test: also the Khronos validation layer, which every rendering test turns on
setup-test: setup
	@scripts/install-packages.sh $(TEST_PACKAGES)

## build: the release binary
build: setup
	$(CARGO) build --release --locked

## render: every figure of the practical into out/ (each image, and one contact sheet per figure)
render: build
	$(BIN) figures -o $(OUT)

## test: every test (unit, shader compilation, GPU renders with validation, CLI errors)
test: setup-test
	$(CARGO) test --release --locked

## bless: rewrite the golden images of tests/golden/ from this device's renders (on purpose: review the diff)
bless: setup-test
	VK_RENDER_BLESS=1 $(CARGO) test --release --locked --test golden -- images_match_the_golden_images

clean:
	$(CARGO) clean
	rm -rf $(OUT)

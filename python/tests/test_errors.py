"""Every error is an exception of its class with the command line's message: never an abort or a hang."""

import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import vk_render
from conftest import FIG1, ROOT, cli


@pytest.mark.parametrize(
    "sets, flags",
    [
        ({"material.grey.kd": -1}, ["--set", "material.grey.kd=-1"]),
        ({"material.nope.kd": 0.5}, ["--set", "material.nope.kd=0.5"]),
        ({"image.width": 0}, ["--set", "image.width=0"]),
        ({"material.grey.brdf": "phang"}, ["--set", "material.grey.brdf=phang"]),
    ],
)
def test_a_bad_value_is_a_scene_error_with_the_command_lines_message(renderer, tmp_path, sets, flags):
    done = cli("render", FIG1, "-o", tmp_path / "x.png", *flags, check=False)
    assert done.returncode == 1
    with pytest.raises(vk_render.SceneError) as raised:
        renderer.render(FIG1, set=sets)
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, vk_render.Error)
    assert f"error: {raised.value}" == done.stderr.strip()
    # Scene.with_set says the same.
    with pytest.raises(vk_render.SceneError) as again:
        vk_render.Scene.load(FIG1).with_set(sets)
    assert str(again.value) == str(raised.value)


def test_a_bad_scene_file_is_a_scene_error(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[image]\nwidth = 'wide'\n")
    with pytest.raises(vk_render.SceneError, match=r"bad.toml: line 2.*width"):
        vk_render.Scene.load(bad)
    with pytest.raises(vk_render.SceneError, match="missing.toml"):
        vk_render.render(tmp_path / "missing.toml")
    with pytest.raises(TypeError, match="vk_render.Scene or a path"):
        vk_render.render(42)
    with pytest.raises(vk_render.SceneError, match="set material.grey.kd: <object .* is not a value of a scene"):
        vk_render.render(FIG1, set={"material.grey.kd": object()})


def test_no_such_device_is_a_device_error():
    with pytest.raises(vk_render.DeviceError, match='--device "no-such-gpu" matches no Vulkan device') as raised:
        vk_render.Renderer(device="no-such-gpu")
    assert isinstance(raised.value, RuntimeError)


def test_an_unreadable_image_to_check_is_an_error(tmp_path):
    (tmp_path / "not.png").write_text("hello")
    with pytest.raises(vk_render.Error, match="not.png: not a PNG or JPEG"):
        vk_render.check(tmp_path / "not.png", "fig1-lambert")
    with pytest.raises(ValueError, match=r"\(height, width, 3\)"):
        vk_render.check(np.zeros((4, 4), np.uint8), "fig1-lambert")


def test_a_panic_in_rust_is_an_exception_and_the_renderer_goes_on(renderer):
    with pytest.raises(vk_render.Error, match="vk-render panicked .*: on purpose"):
        vk_render._native._panic_for_tests("on purpose")
    assert renderer.render(FIG1, width=30, height=20).shape == (20, 30, 3)


# A long call in a child process, and the child's own clock from the SIGINT to the KeyboardInterrupt.
CHILD = textwrap.dedent(
    """
    import signal, sys, time, vk_render
    # Python's own Ctrl-C handler even where SIGINT came ignored (a shell's background job): the test is of
    # vk_render's answer to it, not of how the suite was started.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    sky = {"environment.builtin": "sky", "environment.mode": "exact"}
    call = sys.argv[1]
    print("started", flush=True)
    try:
        if call == "render":
            vk_render.render("assets/scenes/fig1-lambert.toml", width=400, height=300, set=sky)
        elif call == "reference":
            vk_render.reference("assets/scenes/fig1-lambert.toml", width=800, height=600, set=sky)
        else:
            vk_render._native._busy_for_tests(60)
    except KeyboardInterrupt:
        print("interrupted after", time.monotonic() - float(sys.stdin.readline()), flush=True)
        # The renderer goes on after an interruption.
        print(vk_render.render("assets/scenes/fig1-lambert.toml", width=20, height=10).shape, flush=True)
        sys.exit(0)
    print("finished without an interruption", flush=True)
    """
)


@pytest.mark.alone
@pytest.mark.parametrize("call", ["busy", "render", "reference"])
def test_ctrl_c_raises_keyboard_interrupt_within_a_second(call):
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, call], cwd=ROOT, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
    )
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(1.5)  # well inside the call (each takes many seconds)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        child.stdin.write(f"{sent}\n")
        child.stdin.flush()
        out, err = child.communicate(timeout=30)
    finally:
        # A child that did not stop is not left rendering beside the tests that follow.
        child.kill()
        child.wait()
    lines = out.splitlines()
    assert lines and lines[0].startswith("interrupted after"), (out, err)
    assert float(lines[0].split()[-1]) < 1.0, out
    assert lines[1] == "(10, 20, 3)"

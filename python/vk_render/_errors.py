"""vk_render's exceptions (the Rust half raises these same classes)."""


class Error(Exception):
    """Anything vk-render reports: the root of its exceptions."""


class SceneError(Error, ValueError):
    """A bad scene, key or value: the message is the command line's one line, naming the file, key and value."""


class DeviceError(Error, RuntimeError):
    """No Vulkan, no usable device, a failed Vulkan call, or a validation-layer message (validate=True)."""


class SceneWarning(UserWarning):
    """What is legal in a scene but probably not meant (no object, no light, a term view some objects cannot
    show), and where a .brdf file's BRDF gave NaN, an infinity or a negative value: the warnings `vk-render`
    prints, issued through Python's warnings module when a scene renders or a material is studied."""

//! `vk-render devices`: the Vulkan devices and which one is used by default.

use vk_render::vulkan::{list_devices, preferred_device, Instance};

/// Lists the devices, marking the default.
pub fn run(validate: bool) -> anyhow::Result<()> {
    let instance = Instance::new(validate, &[])?;
    let devices = list_devices(&instance)?;
    if devices.is_empty() {
        anyhow::bail!("no Vulkan device was found. {}", vk_render::vulkan::INSTALL_HINT);
    }
    let preferred = preferred_device(&instance, &devices, None).ok().map(|((_, info), _)| info.index);
    for (_, info) in &devices {
        let marker = if Some(info.index) == preferred { "*" } else { " " };
        println!(
            "{marker} {}: {} ({}, Vulkan {}) {}",
            info.index,
            info.name,
            info.kind_name(),
            info.api_version_string(),
            info.driver
        );
    }
    println!("(* = used when --device is not given)");
    Ok(())
}

//! The validation net, proven: misuses and missing dependencies recorded on purpose (here only, never from
//! the command line) must be reported, so that a test that sees no message is clean, not deaf.

use std::io::Write;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::*;

fn validating_device() -> Arc<Device> {
    let instance = Instance::new(true, &[]).expect("the Vulkan loader and the validation layer (make setup-test)");
    let device = Device::new(Arc::new(instance), None, &[], None).expect("a Vulkan device");
    assert!(device.instance.take_validation_messages().is_empty(), "messages before any misuse");
    device
}

/// Whether one of `messages` has the identifier `id` (a VUID, or a synchronization hazard's name).
fn reported(messages: &[String], id: &str) -> bool {
    messages.iter().any(|m| m.contains(&format!("[{id}]")))
}

#[test]
fn the_validation_layer_reports_a_misuse() {
    let device = validating_device();
    // Anisotropic filtering without the samplerAnisotropy feature: invalid, yet harmless on any driver, as a
    // maximum anisotropy of 1 is no anisotropy at all.
    let info = vk::SamplerCreateInfo::default().anisotropy_enable(true).max_anisotropy(1.0);
    // SAFETY: the sampler, if made, is destroyed at once and never used.
    unsafe {
        if let Ok(sampler) = device.raw.create_sampler(&info, None) {
            device.raw.destroy_sampler(sampler, None);
        }
    }
    let messages = device.instance.take_validation_messages();
    assert!(reported(&messages, "VUID-VkSamplerCreateInfo-anisotropyEnable-01070"), "{messages:?}");
}

#[test]
fn synchronization_validation_reports_two_unordered_transfer_writes() {
    // Every layer with synchronization validation on sees hazards between transfer commands: two fills of
    // one buffer with no barrier between them write after write.
    let device = validating_device();
    let desc = BufferDesc { size: 4096, usage: vk::BufferUsageFlags::TRANSFER_DST, location: MemoryLocation::GpuOnly };
    let buffer = device.create_buffer(desc, "twice-filled buffer").expect("a small buffer");
    device
        .submit_and_wait(|cmd| {
            // SAFETY: the buffer outlives the submission, which this call waits for.
            unsafe {
                device.raw.cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, 0);
                device.raw.cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, 1);
            }
            Ok(())
        })
        .expect("the submission runs");
    let messages = device.instance.take_validation_messages();
    assert!(reported(&messages, "SYNC-HAZARD-WRITE-AFTER-WRITE"), "synchronization validation is off: {messages:?}");
}

#[test]
fn synchronization_validation_reports_a_missing_dependency_after_a_render() {
    // The shape of every pass of the renderer: dynamic rendering clears and stores a colour attachment, then
    // a barrier moves the image to a copy's layout. Here that barrier's source scope is empty, so its layout
    // transition (a write) is not ordered after the pass's store: the mistake a rewrite of the passes'
    // synchronisation could make, which only a layer that sees inside dynamic rendering reports.
    let device = validating_device();
    let desc = ImageDesc::plain(
        64,
        64,
        vk::Format::R8G8B8A8_UNORM,
        vk::SampleCountFlags::TYPE_1,
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        vk::ImageAspectFlags::COLOR,
    );
    let image = device.create_image(desc, "render target with a missing dependency").expect("a small image");
    let range = image.full_range();
    let nothing: Access = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
    let attachment: Access =
        (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE);
    let copy: Access = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ);
    device
        .submit_and_wait(|cmd| {
            let barrier = |old, new, src, dst| {
                let barriers = [layout_transition(image.raw, range, old, new, src, dst)];
                // SAFETY: the image outlives the submission, which this call waits for.
                unsafe {
                    device
                        .raw
                        .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barriers))
                };
            };
            barrier(vk::ImageLayout::UNDEFINED, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, nothing, attachment);
            let colour = [vk::RenderingAttachmentInfo::default()
                .image_view(image.view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)];
            let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: 64, height: 64 } };
            let rendering = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&colour);
            // SAFETY: as above; the pass records nothing but its clear and store.
            unsafe {
                device.raw.cmd_begin_rendering(cmd, &rendering);
                device.raw.cmd_end_rendering(cmd);
            }
            // The missing dependency: `nothing` where the pass's (COLOR_ATTACHMENT_OUTPUT, write) belongs.
            barrier(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, nothing, copy);
            Ok(())
        })
        .expect("the submission runs");
    let messages = device.instance.take_validation_messages();
    let layer = device.instance.validation_layer_version().expect("validation is on");
    if layer >= SYNC_VALIDATION_SEES_DYNAMIC_RENDERING {
        assert!(
            reported(&messages, "SYNC-HAZARD-WRITE-AFTER-WRITE"),
            "validation layer {} did not report the missing dependency: {messages:?}",
            version_string(layer)
        );
    } else if !reported(&messages, "SYNC-HAZARD-WRITE-AFTER-WRITE") {
        // Past the test harness's capture, on purpose: the suite says once that this stage is blind here.
        let _ = writeln!(
            std::io::stderr(),
            "NOTE: validation layer {} cannot see hazards inside dynamic rendering (from {} on it can): this \
             stage does not check the render passes' synchronisation; `make test-current` does",
            version_string(layer),
            version_string(SYNC_VALIDATION_SEES_DYNAMIC_RENDERING)
        );
    }
}

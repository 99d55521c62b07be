//! The device layer on the real driver: validation errors are caught, not just printed, and
//! the device reports what it can do.

use crate::common;

use leakless_device::{vk, Buffer, BufferDesc, DeviceError, MemoryLocation};

#[test]
fn a_validation_error_is_an_error() {
    let Some(gpu) = common::gpu() else { return };
    if !gpu.capabilities().validation {
        if std::env::var("LEAKLESS_REQUIRE_DEVICE").as_deref() == Ok("1") {
            panic!("validation layers are not installed (tools/install-deps installs them)");
        }
        eprintln!("*** SKIPPED: validation layers not installed ***");
        return;
    }
    gpu.check_validation().expect("clean so far");
    // An empty usage mask is invalid (VUID-VkBufferCreateInfo-usage-requiredbitmask).
    let desc = BufferDesc {
        name: "invalid on purpose",
        size: 64,
        usage: vk::BufferUsageFlags::empty(),
        location: MemoryLocation::CpuToGpu,
    };
    let _buffer = Buffer::new(&gpu, &desc);
    match gpu.check_validation() {
        Err(DeviceError::Validation { count, first }) => {
            assert!(count >= 1);
            assert!(first.contains("usage"), "{first}");
        }
        other => panic!("the invalid buffer went unnoticed: {other:?}"),
    }
    gpu.check_validation().expect("errors are drained once reported");
}

#[test]
fn device_report_is_complete() {
    let Some(gpu) = common::gpu() else { return };
    let r = gpu.report();
    assert!(!r.name.is_empty() && !r.driver.is_empty());
    assert!(r.api_version >= (1, 3, 0));
    assert!(r.rejected.is_none());
    assert!(r.subgroup_size >= 1, "reported, never assumed");
    assert!(r.timestamp_period_ns > 0.0);
}

#[test]
fn buffer_writes_are_bounds_checked() {
    let Some(gpu) = common::gpu() else { return };
    let desc = BufferDesc {
        name: "small",
        size: 16,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER,
        location: MemoryLocation::CpuToGpu,
    };
    let b = Buffer::new(&gpu, &desc).unwrap();
    b.write(0, &[1u8; 16]).unwrap();
    let err = b.write(8, &[1u8; 16]).unwrap_err();
    assert!(matches!(err, DeviceError::Capacity { capacity: 16, requested: 24, .. }), "{err}");
    let mut back = [0u8; 16];
    b.read(0, &mut back).unwrap();
    assert_eq!(back, [1u8; 16]);
}

/// Two handles of one pool resource would track its hazards apart (no barrier between their
/// uses): the graph refuses the second, naming the resource.
#[test]
fn the_graph_refuses_a_second_handle_to_one_resource() {
    let Some(gpu) = common::gpu() else { return };
    let mut runner = leakless_graph::GraphRunner::new(&gpu, 1).unwrap();
    let mut graph = runner.graph(&gpu).unwrap();
    let desc = |name| BufferDesc {
        name,
        size: 64,
        usage: vk::BufferUsageFlags::STORAGE_BUFFER,
        location: MemoryLocation::GpuOnly,
    };
    let _first = graph.buffer(&desc("counts")).unwrap();
    let _other = graph.buffer(&desc("other counts")).expect("another name is another resource");
    let err = graph.buffer(&desc("counts")).unwrap_err().to_string();
    assert!(err.contains("\"counts\"") && err.contains("twice"), "{err}");
    let image = leakless_device::ImageDesc {
        name: "layer",
        extent: vk::Extent2D { width: 4, height: 4 },
        format: vk::Format::R32G32B32A32_SFLOAT,
        usage: vk::ImageUsageFlags::STORAGE,
    };
    let _layer = graph.image(&image).unwrap();
    assert!(graph.image(&image).is_err());
    let _upload = graph.upload("params", vk::BufferUsageFlags::UNIFORM_BUFFER, &[0u8; 16]).unwrap();
    assert!(graph.upload("params", vk::BufferUsageFlags::UNIFORM_BUFFER, &[0u8; 16]).is_err());
}

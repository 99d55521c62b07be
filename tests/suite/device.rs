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

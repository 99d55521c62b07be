//! A pass's parameter block: a small host-visible uniform buffer written before each run.

use ash::vk;
use bytemuck::Pod;
use leakless_device::{Buffer, BufferDesc, Gpu, MemoryLocation};

use crate::error::Result;

pub struct Uniform<T: Pod> {
    pub buffer: Buffer,
    _marker: std::marker::PhantomData<T>,
}

impl<T: Pod> Uniform<T> {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let desc = BufferDesc {
            name,
            size: std::mem::size_of::<T>() as u64,
            usage: vk::BufferUsageFlags::UNIFORM_BUFFER,
            location: MemoryLocation::CpuToGpu,
        };
        Ok(Uniform { buffer: Buffer::new(gpu, &desc)?, _marker: Default::default() })
    }

    /// Sets the parameters of the next run (the previous run has completed: the graph
    /// runner waits for every submission).
    pub fn set(&self, value: &T) -> Result<()> {
        Ok(self.buffer.write(0, bytemuck::bytes_of(value))?)
    }
}

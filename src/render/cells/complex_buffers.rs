//! A cell complex's arrays on the device, bound by the cells pass and by the GPU march of rays.

use std::sync::Arc;

use ash::vk;

use crate::cells::PackedComplex;
use crate::render::shader_interface::{
    BINDING_CELLS_CELLS, BINDING_CELLS_GREY, BINDING_CELLS_MAPS,
};
use crate::vk::{Bind, Buffer, Context, VkResult};

/// A complex's arrays on the device (bindings 0-2 of `cells_march.glsl`).
pub(in crate::render) struct ComplexBuffers {
    cells: Buffer,
    grey: Buffer,
    maps: Buffer,
}

impl ComplexBuffers {
    /// Uploads `complex`'s arrays; `name` labels them.
    pub(in crate::render) fn upload(
        ctx: &Arc<Context>,
        complex: &PackedComplex,
        name: &str,
    ) -> VkResult<ComplexBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let upload = |bytes: &[u8], what: &str| {
            Buffer::with_data(
                ctx,
                &Self::nonempty(bytes),
                storage,
                &format!("{name} {what}"),
            )
        };
        Ok(ComplexBuffers {
            cells: upload(bytemuck::cast_slice(&complex.cells), "cells")?,
            grey: upload(bytemuck::cast_slice(&complex.grey), "grey cells")?,
            maps: upload(bytemuck::cast_slice(&complex.maps), "cell maps")?,
        })
    }

    /// Their bindings, 0 to 2.
    pub(in crate::render) fn binds(&self) -> [Bind<'_>; 3] {
        [
            Bind::Storage(BINDING_CELLS_CELLS, &self.cells),
            Bind::Storage(BINDING_CELLS_GREY, &self.grey),
            Bind::Storage(BINDING_CELLS_MAPS, &self.maps),
        ]
    }

    /// `bytes`, or one 64-byte record where there are none: storage buffers may not be empty (a
    /// complex with no grey cell still binds one record).
    pub(in crate::render) fn nonempty(bytes: &[u8]) -> Vec<u8> {
        if bytes.is_empty() {
            vec![0u8; 64]
        } else {
            bytes.to_vec()
        }
    }
}

//! Safe code may drop what a submitted frame still reads: `relief::vk` destroys it only once the
//! GPU is past that frame, so the validation layer sees no use of a destroyed object. Ranges that
//! safe code gets wrong are errors, not undefined behaviour.

#![deny(clippy::undocumented_unsafe_blocks)]

mod common;

use relief::vk::{
    raw as vk, upload_mips, whole_color_region, Bind, Buffer, CommandSlot, DescriptorLayout,
    DescriptorPool, Image, ImageDesc, MemoryLocation, Readback, Sampler, TimestampPool,
};

const SIDE: u32 = 256;

fn pattern(len: usize, seed: u8) -> Vec<u8> {
    (0..len)
        .map(|k| (k as u8).wrapping_mul(31) ^ seed)
        .collect()
}

fn source_image(ctx: &std::sync::Arc<relief::vk::Context>, texels: &[u8]) -> Image {
    let desc = ImageDesc {
        width: SIDE,
        height: SIDE,
        format: vk::Format::R8G8B8A8_UNORM,
        mip_levels: 1,
        usage: vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST
            | vk::ImageUsageFlags::SAMPLED,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, "lifetime test image").expect("image");
    upload_mips(
        ctx,
        &image,
        &[texels],
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    )
    .expect("upload");
    image
}

#[test]
fn buffers_and_images_dropped_while_their_frame_is_in_flight_outlive_it() {
    let Some(ctx) =
        common::device("buffers_and_images_dropped_while_their_frame_is_in_flight_outlive_it")
    else {
        return;
    };
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    // Large enough that the copy is still running on a software rasteriser when the host drops it.
    let bytes = pattern(16 << 20, 7);
    let texels = pattern((SIDE * SIDE * 4) as usize, 3);
    let sampler = Sampler::new(
        &ctx,
        vk::Filter::LINEAR,
        vk::SamplerAddressMode::REPEAT,
        "lifetime test sampler",
    )
    .expect("sampler");
    let mut slot = CommandSlot::new(&ctx, "lifetime test slot").expect("slot");
    let copied = Readback::new(&ctx, bytes.len() as u64, "copied buffer").expect("readback");
    let pixels = Readback::new(&ctx, texels.len() as u64, "copied image").expect("readback");
    let extra = Readback::new(&ctx, 64, "copied temporary").expect("readback");
    for round in 0..3 {
        let storage = usage | vk::BufferUsageFlags::STORAGE_BUFFER;
        let source = Buffer::with_data(&ctx, &bytes, storage, "in-flight source").expect("buffer");
        let image = source_image(&ctx, &texels);
        let layout = DescriptorLayout::new(
            &ctx,
            &[
                (0, vk::DescriptorType::STORAGE_BUFFER),
                (1, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            ],
            vk::ShaderStageFlags::COMPUTE,
            "lifetime test layout",
        )
        .expect("layout");
        let pool = DescriptorPool::new(&ctx, 1, 2, "lifetime test pool").expect("pool");
        let set = pool
            .allocate(
                &layout,
                &[
                    Bind::Storage(0, &source),
                    Bind::Texture(1, image.view(), &sampler),
                ],
            )
            .expect("set");
        slot.submit(|rec| {
            let written = (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            );
            copied.record_copy_from_buffer(rec, &source, written)?;
            pixels.record_copy_from_image(rec, &image, whole_color_region(SIDE, SIDE))?;
            // Dropped while the recording is still open: it must outlive the submission too.
            let temporary =
                Buffer::with_data(&ctx, &[round as u8; 64], usage, "temporary").expect("buffer");
            extra.record_copy_from_buffer(rec, &temporary, written)?;
            drop(temporary);
            Ok(())
        })
        .expect("submit");
        // The frame is in flight: drop everything it reads, the set and its pool first.
        drop(set);
        drop(pool);
        drop(layout);
        drop(source);
        drop(image);
        slot.wait().expect("wait");
        assert_eq!(copied.bytes().expect("bytes"), &bytes[..], "round {round}");
        assert_eq!(pixels.bytes().expect("bytes"), &texels[..], "round {round}");
        assert_eq!(
            extra.bytes().expect("bytes"),
            &[round as u8; 64],
            "round {round}"
        );
    }
    drop(slot);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn out_of_range_fills_and_copies_are_errors() {
    let Some(ctx) = common::device("out_of_range_fills_and_copies_are_errors") else {
        return;
    };
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let buffer = Buffer::new(&ctx, 64, usage, MemoryLocation::GpuOnly, "fill target").expect("ok");
    let texels = pattern((SIDE * SIDE * 4) as usize, 5);
    let image = source_image(&ctx, &texels);
    let small = Readback::new(&ctx, 16, "small readback").expect("readback");
    ctx.one_shot(|rec| {
        for (offset, size) in [(0, 68), (64, 4), (u64::MAX - 3, 8), (2, 4), (0, 6)] {
            let e = rec
                .fill_buffer(&buffer, offset, size, 0)
                .expect_err("out of range or misaligned");
            assert!(e.to_string().contains("fill target"), "{e}");
        }
        rec.fill_buffer(&buffer, 60, 4, 0)
            .expect("the last word fits");
        let past_edge = whole_color_region(SIDE + 1, 1);
        assert!(small
            .record_copy_from_image(rec, &image, past_edge)
            .is_err());
        let too_big_for_buffer = whole_color_region(SIDE, 1);
        assert!(small
            .record_copy_from_image(rec, &image, too_big_for_buffer)
            .is_err());
        let mut wrong_level = whole_color_region(1, 1);
        wrong_level.image_subresource.mip_level = 1;
        assert!(small
            .record_copy_from_image(rec, &image, wrong_level)
            .is_err());
        small.record_copy_from_image(rec, &image, whole_color_region(4, 1))
    })
    .expect("the in-range commands submit");
    assert_eq!(small.bytes().expect("bytes"), &texels[..16]);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn timestamps_beyond_the_pool_or_never_written_are_errors() {
    let Some(ctx) = common::device("timestamps_beyond_the_pool_or_never_written_are_errors") else {
        return;
    };
    let pool = TimestampPool::new(&ctx, 2, "lifetime test timestamps").expect("timestamps");
    let e = pool.read_ticks(3).expect_err("more than the pool holds");
    assert!(e.to_string().contains("3 timestamps"), "{e}");
    // Nothing ever wrote them: an error at once, not a wait for the GPU timeout.
    let started = std::time::Instant::now();
    assert!(pool.read_ticks(2).is_err());
    assert!(started.elapsed() < ctx.gpu_timeout());
    assert_eq!(
        pool.read_ticks(0).expect("no timestamps"),
        Vec::<u64>::new()
    );
    drop(pool);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_timestamp_written_twice_without_a_reset_is_an_error() {
    let Some(ctx) = common::device("a_timestamp_written_twice_without_a_reset_is_an_error") else {
        return;
    };
    let pool = TimestampPool::new(&ctx, 1, "written twice").expect("timestamps");
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|rec| {
        pool.write(rec, all, 0)?;
        assert!(
            pool.write(rec, all, 0).is_err(),
            "a second write is refused"
        );
        Ok(())
    })
    .expect("submission");
    assert_eq!(pool.read_ticks(1).expect("one timestamp").len(), 1);
    // SAFETY: the one-shot that wrote the pool has returned, so its work has finished.
    unsafe { pool.reset() };
    ctx.one_shot(|rec| pool.write(rec, all, 0))
        .expect("written again after the reset");
    drop(pool);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn binds_the_layout_lacks_are_errors() {
    let Some(ctx) = common::device("binds_the_layout_lacks_are_errors") else {
        return;
    };
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::UNIFORM_BUFFER;
    let buffer = Buffer::new(&ctx, 256, usage, MemoryLocation::GpuOnly, "bound").expect("buffer");
    let layout = DescriptorLayout::new(
        &ctx,
        &[(0, vk::DescriptorType::STORAGE_BUFFER)],
        vk::ShaderStageFlags::COMPUTE,
        "one storage buffer",
    )
    .expect("layout");
    let pool = DescriptorPool::new(&ctx, 2, 2, "mismatch pool").expect("pool");
    let wrong_kind = pool.allocate(&layout, &[Bind::Uniform(0, &buffer)]);
    assert!(
        wrong_kind.is_err(),
        "a uniform where the layout has storage"
    );
    let wrong_binding = pool.allocate(&layout, &[Bind::Storage(1, &buffer)]);
    assert!(wrong_binding.is_err(), "binding 1 of a layout with only 0");
    let set = pool
        .allocate(&layout, &[Bind::Storage(0, &buffer)])
        .expect("the matching bind");
    // SAFETY: the set was never bound, so no submission uses it.
    let rewritten = unsafe { set.rewrite(&[Bind::Uniform(0, &buffer)]) };
    assert!(rewritten.is_err());
    drop(set);
    drop(pool);
    common::assert_no_validation_errors(&ctx);
}

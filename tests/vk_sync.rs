//! Synchronisation in `relief::vk`: one-shot submissions from several threads at once, and GPU
//! results read on the host only through a copy with the host-read barrier, once the submission
//! that carries the copy has finished (waited for when it has not).

mod common;

use std::sync::Arc;

use relief::vk::{
    raw as vk, read_mip, upload_mips, Buffer, Context, Image, ImageDesc, MemoryLocation, Readback,
};

/// Uploads `pattern` through a staging buffer into device-local memory and reads it back.
fn round_trip(ctx: &Arc<Context>, pattern: &[u8], name: &str) -> Vec<u8> {
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let staging = Buffer::with_data(ctx, pattern, usage, name).expect("staging");
    let size = pattern.len() as u64;
    let gpu = Buffer::new(ctx, size, usage, MemoryLocation::GpuOnly, name).expect("gpu buffer");
    let back = Readback::new(ctx, size, name).expect("readback");
    ctx.one_shot(|rec| {
        rec.copy_buffer(&staging, &gpu);
        let written = (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
        );
        back.record_copy_from_buffer(rec, &gpu, written)
    })
    .expect("one-shot");
    back.bytes().expect("readback bytes").to_vec()
}

/// Fills a device-local buffer 16 bytes at a time (many commands, so recordings on different
/// threads overlap) and reads it back.
fn fill_and_read(ctx: &Arc<Context>, words: &[u32], name: &str) -> Vec<u32> {
    let size = words.len() as u64 * 16;
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let gpu = Buffer::new(ctx, size, usage, MemoryLocation::GpuOnly, name).expect("gpu buffer");
    let back = Readback::new(ctx, size, name).expect("readback");
    ctx.one_shot(|rec| {
        for (i, &word) in words.iter().enumerate() {
            rec.fill_buffer(&gpu, i as u64 * 16, 16, word)?;
        }
        let written = (
            vk::PipelineStageFlags2::CLEAR,
            vk::AccessFlags2::TRANSFER_WRITE,
        );
        back.record_copy_from_buffer(rec, &gpu, written)
    })
    .expect("one-shot");
    bytemuck::pod_collect_to_vec::<u8, u32>(back.bytes().expect("bytes"))
        .chunks_exact(4)
        .map(|c| c[0])
        .collect()
}

#[test]
fn one_shot_from_many_threads_is_race_free() {
    let Some(ctx) = common::device("one_shot_from_many_threads_is_race_free") else {
        return;
    };
    let threads: Vec<_> = (0..6u32)
        .map(|t| {
            let ctx = ctx.clone();
            std::thread::spawn(move || {
                for k in 0..12u32 {
                    let words: Vec<u32> = (0..512u32).map(|i| t << 24 | k << 16 | i).collect();
                    let got = fill_and_read(&ctx, &words, &format!("thread {t} fill {k}"));
                    assert!(got == words, "thread {t} round {k}: data differs");
                    let pattern: Vec<u8> = (0..256u32).map(|i| (i ^ t ^ k) as u8).collect();
                    let got = round_trip(&ctx, &pattern, &format!("thread {t} upload {k}"));
                    assert!(got == pattern, "thread {t} upload {k}: data differs");
                }
            })
        })
        .collect();
    for t in threads {
        t.join().expect("thread");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn readback_refuses_bytes_without_a_recorded_copy() {
    let Some(ctx) = common::device("readback_refuses_bytes_without_a_recorded_copy") else {
        return;
    };
    let back = Readback::new(&ctx, 64, "unread readback").expect("readback");
    let e = back.bytes().expect_err("no copy was recorded").to_string();
    assert!(e.contains("unread readback"), "{e}");
    drop(back);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn device_local_data_round_trips_through_a_readback() {
    let Some(ctx) = common::device("device_local_data_round_trips_through_a_readback") else {
        return;
    };
    let pattern: Vec<u8> = (0..1000u32).map(|i| (i * 7 % 256) as u8).collect();
    assert_eq!(round_trip(&ctx, &pattern, "round trip"), pattern);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn read_mip_returns_what_was_uploaded() {
    let Some(ctx) = common::device("read_mip_returns_what_was_uploaded") else {
        return;
    };
    let desc = ImageDesc {
        width: 13,
        height: 7,
        format: vk::Format::R8_UNORM,
        mip_levels: 2,
        usage: vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST
            | vk::ImageUsageFlags::SAMPLED,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(&ctx, desc, "read_mip test").expect("image");
    let level0: Vec<u8> = (0..13 * 7).map(|i| (i * 3) as u8).collect();
    let level1: Vec<u8> = (0..6 * 3).map(|i| 255 - i as u8).collect();
    let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    upload_mips(&ctx, &image, &[&level0, &level1], layout).expect("upload");
    assert_eq!(read_mip(&ctx, &image, 0, layout).expect("mip 0"), level0);
    assert_eq!(read_mip(&ctx, &image, 1, layout).expect("mip 1"), level1);
    drop(image);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_readback_is_read_only_after_the_submission_that_fills_it() {
    let Some(ctx) = common::device("a_readback_is_read_only_after_the_submission_that_fills_it")
    else {
        return;
    };
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let gpu = Buffer::new(&ctx, 64, usage, MemoryLocation::GpuOnly, "filled").expect("buffer");
    let back = Readback::new(&ctx, 64, "pending readback").expect("readback");
    let written = (
        vk::PipelineStageFlags2::CLEAR,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    let fill = |rec: &relief::vk::Recording, word: u32| -> relief::vk::VkResult<()> {
        rec.fill_buffer(&gpu, 0, 64, word)?;
        back.record_copy_from_buffer(rec, &gpu, written)
    };
    // Inside its recording the copy has not gone out: no bytes.
    ctx.one_shot(|rec| {
        fill(rec, 7)?;
        let e = back.bytes().expect_err("not submitted yet").to_string();
        assert!(e.contains("submitted"), "{e}");
        Ok(())
    })
    .expect("one-shot");
    let words = |b: &[u8]| bytemuck::pod_collect_to_vec::<u8, u32>(b);
    assert!(words(back.bytes().expect("filled")).iter().all(|&w| w == 7));
    // A recording abandoned by an error never goes out: its copy is never readable.
    let abandoned = ctx.one_shot(|rec| {
        fill(rec, 8)?;
        Err::<(), _>(relief::vk::VkError::Invalid("abandoned".into()))
    });
    assert!(abandoned.is_err());
    let e = back.bytes().expect_err("abandoned").to_string();
    assert!(e.contains("submitted"), "{e}");
    // A frame slot's submission returns before the GPU is done: reading waits for it.
    let mut slot = relief::vk::CommandSlot::new(&ctx, "readback slot").expect("slot");
    slot.submit(|rec| fill(rec, 9)).expect("submits");
    let read = words(back.bytes().expect("waited for"));
    assert!(read.iter().all(|&w| w == 9));
    slot.wait().expect("waits");
    drop(slot);
    common::assert_no_validation_errors(&ctx);
}

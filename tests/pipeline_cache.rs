//! The pipeline cache: data from one context seeds the next; garbage, truncated or foreign data
//! is ignored (an empty cache, pipelines still created, no validation errors), never a crash.

mod common;

use std::sync::Arc;

use relief::render::PyramidPass;
use relief::vk::{check_pipeline_cache_header, CacheIdentity, Context, ContextOptions};

fn with_cache(test: &str, bytes: Option<Vec<u8>>) -> Option<Arc<Context>> {
    let options = ContextOptions::default().with_pipeline_cache(bytes);
    common::device_with(test, &options)
}

/// Creates pipelines through the context's cache and returns the cache's data.
fn make_pipelines(ctx: &Arc<Context>) -> Vec<u8> {
    let pass = PyramidPass::new(ctx, "r32f").expect("pipelines are created");
    drop(pass);
    ctx.pipeline_cache_data().expect("cache data")
}

fn own_data(test: &str) -> Option<Vec<u8>> {
    let ctx = with_cache(test, None)?;
    assert!(!ctx.pipeline_cache_seeded());
    let data = make_pipelines(&ctx);
    let identity = CacheIdentity::of(ctx.info());
    assert_eq!(check_pipeline_cache_header(&data, &identity), Ok(()));
    common::assert_no_validation_errors(&ctx);
    Some(data)
}

#[test]
fn cache_data_seeds_a_new_context() {
    let test = "cache_data_seeds_a_new_context";
    let Some(data) = own_data(test) else {
        return;
    };
    let ctx = with_cache(test, Some(data.clone())).expect("device");
    assert!(ctx.pipeline_cache_seeded(), "own data is accepted");
    let again = make_pipelines(&ctx);
    assert!(again.len() >= 32);
    common::assert_no_validation_errors(&ctx);
    let merged = with_cache(test, None).expect("device");
    assert!(merged.merge_pipeline_cache(&data).expect("merge"));
    assert!(merged.pipeline_cache_seeded());
    make_pipelines(&merged);
    common::assert_no_validation_errors(&merged);
}

#[test]
fn bad_cache_data_is_ignored() {
    let test = "bad_cache_data_is_ignored";
    let Some(good) = own_data(test) else {
        return;
    };
    let mut foreign = good.clone();
    foreign[16] ^= 0xff; // pipelineCacheUUID
    let mut other_vendor = good.clone();
    other_vendor[8] ^= 0x01;
    let garbage: Vec<u8> = (0..4096u32).map(|k| (k * 131 % 251) as u8).collect();
    let cases = [
        ("garbage", garbage),
        ("truncated header", good[..20].to_vec()),
        ("empty", Vec::new()),
        ("wrong uuid", foreign),
        ("wrong vendor", other_vendor),
    ];
    for (what, bytes) in cases {
        let ctx = with_cache(test, Some(bytes.clone())).expect("device");
        assert!(!ctx.pipeline_cache_seeded(), "{what}: ignored");
        make_pipelines(&ctx);
        assert!(
            !ctx.merge_pipeline_cache(&bytes).expect("merge"),
            "{what}: not merged"
        );
        common::assert_no_validation_errors(&ctx);
    }
}

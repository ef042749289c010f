//! Timestamps are supported on the device, increase monotonically, and convert with a positive period.

mod common;

use relief::vk::{raw as vk, TimestampPool};

#[test]
fn timestamps_are_monotonic_with_positive_period() {
    let Some(ctx) = common::device("timestamps_are_monotonic_with_positive_period") else {
        return;
    };
    let pool = TimestampPool::new(&ctx, 4, "test timestamps").expect("device has timestamps");
    assert!(pool.period_ns() > 0.0, "timestampPeriod must be positive");
    assert!(ctx.info().timestamp_valid_bits > 0);
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|rec| {
        for k in 0..4 {
            pool.write(rec, all, k)?;
        }
        assert!(
            pool.write(rec, all, 4).is_err(),
            "index past capacity is refused"
        );
        Ok(())
    })
    .expect("submission");
    let ticks = pool.read_ticks(4).expect("results");
    for pair in ticks.windows(2) {
        assert!(pair[1] >= pair[0], "timestamps go backwards: {ticks:?}");
        let ms = pool.ticks_to_ms(pair[0], pair[1]);
        assert!(
            (0.0..10_000.0).contains(&ms),
            "implausible interval {ms} ms"
        );
    }
    drop(pool);
    common::assert_no_validation_errors(&ctx);
}

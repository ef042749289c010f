//! The test harness itself: under CI a validation check must not pass vacuously.

mod common;

use common::validation_check;

#[test]
fn ci_without_validation_layer_fails() {
    let why = validation_check(true, false).unwrap_err();
    assert!(why.contains("vulkan-validationlayers"), "{why}");
}

#[test]
fn ci_with_validation_layer_passes() {
    assert_eq!(validation_check(true, true), Ok(()));
}

#[test]
fn outside_ci_a_missing_layer_is_allowed() {
    assert_eq!(validation_check(false, false), Ok(()));
    assert_eq!(validation_check(false, true), Ok(()));
}

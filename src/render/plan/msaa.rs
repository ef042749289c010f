//! Multisampling of the raster passes: how many samples a pixel gets, chosen from what was asked
//! and what the device takes. Relief is traced once per pixel whatever the count (the fragment
//! shader runs per pixel, not per sample), so MSAA smooths geometry edges, including where a
//! relief surface meets another object, and the resolve averages the samples into the frame.

use serde::Serialize;

use crate::vk::VkError;

/// Sample counts a frame may ask for.
pub const SAMPLE_COUNTS: [u32; 4] = [1, 2, 4, 8];

/// The frame's multisampling, for the plan and `--explain`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct MsaaPlan {
    /// Samples per pixel asked for (`--msaa`).
    pub asked: u32,
    /// Samples per pixel drawn: `asked`, or fewer where the device or the frame cannot take them.
    pub samples: u32,
    /// Why `samples` is below `asked`, if it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduced: Option<String>,
}

impl MsaaPlan {
    /// One sample per pixel: no multisampled targets, no resolve.
    pub const SINGLE: MsaaPlan = MsaaPlan {
        asked: 1,
        samples: 1,
        reduced: None,
    };

    /// `asked` samples, clamped to `device_max`; one sample when `probe` (the shadow probe reads
    /// one depth per pixel). Errors on a count other than 1, 2, 4 or 8.
    pub fn choose(asked: u32, device_max: u32, probe: bool) -> Result<MsaaPlan, VkError> {
        if !SAMPLE_COUNTS.contains(&asked) {
            return Err(VkError::Invalid(format!(
                "--msaa must be 1, 2, 4 or 8 samples per pixel, got {asked}"
            )));
        }
        let (samples, reduced) = if probe && asked > 1 {
            (
                1,
                Some("the shadow probe reads one depth per pixel".to_owned()),
            )
        } else if asked > device_max {
            let why = format!("the device takes at most {device_max} samples per pixel");
            (device_max.max(1), Some(why))
        } else {
            (asked, None)
        };
        Ok(MsaaPlan {
            asked,
            samples,
            reduced,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_clamped_to_the_device_and_say_why() {
        assert_eq!(MsaaPlan::choose(4, 8, false).expect("ok").samples, 4);
        let clamped = MsaaPlan::choose(8, 4, false).expect("ok");
        assert_eq!(clamped.samples, 4);
        assert!(clamped.reduced.expect("a reason").contains("at most 4"));
        assert_eq!(MsaaPlan::choose(4, 8, true).expect("ok").samples, 1);
        assert_eq!(MsaaPlan::choose(1, 1, true).expect("ok").reduced, None);
        let bad = MsaaPlan::choose(3, 8, false)
            .expect_err("refused")
            .to_string();
        assert!(bad.contains("1, 2, 4 or 8"), "{bad}");
    }
}

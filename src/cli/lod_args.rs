//! `relief render --lod` and its parameters: level of detail for every relief material of the
//! scene, over whatever `extras.relief.lod` said (the flags are the later word).

use clap::Args;
use relief::scene::{Lod, Scene};

#[derive(Args, Debug, Clone)]
pub struct LodArgs {
    /// Level of detail on every relief material (Drobot's mixed LOD, Ki and Oh's averaged
    /// pyramid); the --lod-* flags imply it.
    #[arg(long)]
    pub lod: bool,
    /// Multiplies the pixel's height-map mip level into the traversal's stop level.
    #[arg(long, value_name = "F")]
    pub lod_factor: Option<f32>,
    /// Added to the stop level, in levels.
    #[arg(long, value_name = "LEVELS", allow_hyphen_values = true)]
    pub lod_bias: Option<f32>,
    /// Fade to normal mapping between these world distances from the eye (nothing is traced
    /// beyond END).
    #[arg(
        long,
        value_name = "START,END",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    pub lod_fade: Vec<f32>,
    /// Stop levels below this end on the averaged pyramid; 0 never.
    #[arg(long, value_name = "LEVEL")]
    pub lod_average_below: Option<u32>,
}

impl LodArgs {
    /// The settings the flags ask for, or `None` when no LOD flag was given.
    pub fn settings(&self) -> anyhow::Result<Option<Lod>> {
        let any = self.lod_factor.is_some()
            || self.lod_bias.is_some()
            || !self.lod_fade.is_empty()
            || self.lod_average_below.is_some();
        if !(self.lod || any) {
            return Ok(None);
        }
        let mut lod = Lod::default();
        lod.factor = self.lod_factor.unwrap_or(lod.factor);
        lod.bias = self.lod_bias.unwrap_or(lod.bias);
        match self.lod_fade[..] {
            [] => {}
            [start, end] => (lod.fade_start, lod.fade_end) = (start, end),
            _ => {
                return Err(super::usage(format!(
                "--lod-fade takes two distances, START,END (e.g. --lod-fade 3,6), got {} values",
                self.lod_fade.len()
            )))
            }
        }
        lod.average_below = self.lod_average_below.unwrap_or(lod.average_below);
        lod.validate("lod")
            .map_err(|e| super::usage(format!("--lod-*: {e}")))?;
        Ok(Some(lod))
    }

    /// Sets the LOD of every relief material of `scene`; how many there were.
    pub fn apply(&self, scene: &mut Scene) -> anyhow::Result<usize> {
        let Some(lod) = self.settings()? else {
            return Ok(0);
        };
        let reliefs = scene.materials.iter_mut().filter_map(|m| m.relief.as_mut());
        Ok(reliefs.map(|r| r.lod = Some(lod)).count())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(fade: &[f32], factor: Option<f32>) -> LodArgs {
        LodArgs {
            lod: false,
            lod_factor: factor,
            lod_bias: None,
            lod_fade: fade.to_vec(),
            lod_average_below: None,
        }
    }

    #[derive(clap::Parser)]
    struct Wrapper {
        #[command(flatten)]
        lod: LodArgs,
    }

    #[test]
    fn lod_fade_takes_start_comma_end_as_documented() {
        use clap::Parser;
        let parsed = Wrapper::try_parse_from(["relief", "--lod-fade", "3,6"]).expect("parses");
        assert_eq!(parsed.lod.lod_fade, [3.0, 6.0]);
        let one = Wrapper::try_parse_from(["relief", "--lod-fade", "3"]).expect("parses");
        let err = one.lod.settings().unwrap_err().to_string();
        assert!(err.contains("START,END"), "{err}");
    }

    #[test]
    fn flags_imply_lod_and_are_checked() {
        assert_eq!(args(&[], None).settings().unwrap(), None);
        let lod = args(&[2.0, 4.0], Some(0.5)).settings().unwrap().unwrap();
        assert_eq!((lod.factor, lod.fade_start, lod.fade_end), (0.5, 2.0, 4.0));
        let err = args(&[5.0, 4.0], None).settings().unwrap_err().to_string();
        assert!(err.contains("lod.fade_end"), "{err}");
    }
}

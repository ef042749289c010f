//! Per-ray steps maps: each method's iterations over the error grid of its first error-against-
//! time configuration (the first field and view at its default budget), kept beside the run so
//! `relief bench` can draw them as heat maps next to the report's error figures. Where a method
//! pays shows where it is slow: grazing slopes for a fixed-step march, deep cracks for a
//! pyramid walk.

/// One method's steps per ray, rows of the ray grid top to bottom.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepsMap {
    /// Method id.
    pub method: String,
    /// Field, view and budget the rays were traced at, for the report.
    pub traced: String,
    /// Columns and rows of the ray grid.
    pub grid: [u32; 2],
    /// Iterations of each ray.
    pub steps: Vec<u32>,
}

impl StepsMap {
    /// The file the map is written to: `steps-<method>.png`.
    pub fn file(&self) -> String {
        format!("steps-{}.png", self.method)
    }

    /// The most steps any ray took: the top of the map's scale.
    pub fn most(&self) -> u32 {
        self.steps.iter().copied().max().unwrap_or(0)
    }

    /// The mean steps per ray.
    pub fn mean(&self) -> f64 {
        if self.steps.is_empty() {
            return 0.0;
        }
        self.steps.iter().map(|&s| f64::from(s)).sum::<f64>() / self.steps.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_names_its_file_and_scale() {
        let map = StepsMap {
            method: "qdm".into(),
            traced: "fbm".into(),
            grid: [2, 2],
            steps: vec![1, 4, 2, 1],
        };
        assert_eq!(map.file(), "steps-qdm.png");
        assert_eq!(map.most(), 4);
        assert_eq!(map.mean(), 2.0);
    }
}

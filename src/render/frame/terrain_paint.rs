//! Painting a layered material's weights on a live renderer: the checks that a material can be
//! painted, the strokes and rule reweighing applied through its painter, and the partial rebuild
//! on the GPU of what they changed (splat texels, blended pyramid regions, nearby AO).

use crate::render::frame::renderer::{FrameOutput, Renderer};
use crate::render::kit::render_error::RenderError;
use crate::render::plan::frame_plan::HeightKey;
use crate::render::terrain::blended_pyramid_pass::time_on_gpu;
use crate::render::terrain::layer_paint::{
    record_paint_copies, LayerPainter, PaintError, PaintReport, StagedPaint,
};
use crate::terrain::{SplatMap, Stroke, TexelRect};
use crate::vk::{RegionTexels, StagedRegions};

impl Renderer {
    /// The painted map of layered material `material`, checked for painting: its plan index.
    fn paintable(&self, material: usize) -> Result<usize, RenderError> {
        let refuse = |why: &str| Err(RenderError::Layers(format!("material {material}: {why}")));
        let Some(h) = self
            .plan
            .heights
            .iter()
            .position(|hp| hp.key == HeightKey::Layers { material })
        else {
            return refuse("not a drawn layered material; only layered weights are painted");
        };
        let hp = &self.plan.heights[h];
        if self.painters[h].is_none() {
            return refuse("the renderer was made without RenderOptions::paintable_layers");
        }
        if let Some(kind) = hp.map {
            return refuse(&format!(
                "its method reads a {} built once from the whole field; paint with a method without one (qdm, pdm, qrm, maxmip, relief, pom)",
                kind.name().replace('_', " ")
            ));
        }
        if hp.mean_pyramid {
            return refuse(
                "its level of detail reads an averaged pyramid built once; paint without --lod",
            );
        }
        Ok(h)
    }

    /// The splat map of layered material `material` as painted so far, if it can be painted:
    /// strokes for [`Renderer::paint_layers`] are in its texels.
    pub fn layer_splat(&self, material: usize) -> Result<&SplatMap, RenderError> {
        let h = self.paintable(material)?;
        Ok(self.painters[h]
            .as_ref()
            .map(LayerPainter::splat)
            .expect("paintable checked the painter"))
    }

    /// Checks `strokes` for [`Renderer::paint_layers`] without applying any.
    pub fn check_paint(&self, material: usize, strokes: &[Stroke]) -> Result<(), RenderError> {
        let h = self.paintable(material)?;
        if let Some(painter) = &self.painters[h] {
            painter.check(strokes)?;
        }
        Ok(())
    }

    /// Paints layered material `material`'s weights with `strokes` (`paint` strokes, centres and
    /// radii in its splat map's texels, all checked first): waits for the frames in flight, which
    /// are returned, then rebuilds on the GPU only what the strokes changed — the splat image
    /// shaded, the blended field and pyramid nodes above the repainted weights, and the AO near
    /// them.
    pub fn paint_layers(
        &mut self,
        material: usize,
        strokes: &[Stroke],
    ) -> Result<(Vec<FrameOutput>, PaintReport), RenderError> {
        let h = self.paintable(material)?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        // Refused before waiting, so that a bad list loses no frame in flight.
        painter.check(strokes)?;
        let retired = self.finish()?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        let staged = painter.paint(strokes).map_err(|e| match e {
            PaintError::Stroke(s) => RenderError::from(s),
            PaintError::Vulkan(v) => RenderError::from(v),
        })?;
        let report = self.rebuild_painted(h, material, &staged, strokes.len())?;
        // The blended heights moved, and with them the relief the shadow maps trace.
        self.invalidate_shadow_maps();
        Ok((retired, report))
    }

    /// Sets layered material `material`'s weights from `weights` (splat texel to weights) over
    /// splat texels `rect`, except where strokes painted by hand (`Renderer::paint_layers`):
    /// what rules derive from an edited elevation. Waits for the frames in flight, which are
    /// returned, and rebuilds what changed as painting does; `None` when nothing changed.
    pub fn reweigh_layers(
        &mut self,
        material: usize,
        rect: TexelRect,
        weights: impl Fn(u32, u32) -> [f32; 4],
    ) -> Result<(Vec<FrameOutput>, Option<PaintReport>), RenderError> {
        let h = self.paintable(material)?;
        let retired = self.finish()?;
        let painter = self.painters[h]
            .as_mut()
            .expect("paintable checked the painter");
        let Some(staged) = painter.reweigh(rect, weights)? else {
            return Ok((retired, None));
        };
        let report = self.rebuild_painted(h, material, &staged, 0)?;
        self.invalidate_shadow_maps();
        Ok((retired, Some(report)))
    }

    /// Rebuilds on the GPU what `staged` changed in layered height map `h` of `material`: the
    /// shading's splat texels, the blended pyramid's regions copied into the drawn height map,
    /// and the AO near them (once the first frame has built it).
    fn rebuild_painted(
        &self,
        h: usize,
        material: usize,
        staged: &StagedPaint,
        strokes: usize,
    ) -> Result<PaintReport, RenderError> {
        let painter = self.painters[h]
            .as_ref()
            .expect("paintable checked the painter");
        let splat_image = self.surface.layer_splat(material);
        let splat_staged = match splat_image {
            Some(image) => {
                let bytes: Vec<Vec<u8>> = staged
                    .splat_rects
                    .iter()
                    .map(|r| painter.splat_bytes(r))
                    .collect();
                let regions: Vec<RegionTexels> = staged
                    .splat_rects
                    .iter()
                    .zip(&bytes)
                    .map(|(r, b)| (0, [r.x0, r.y0, r.width(), r.height()], b.as_slice()))
                    .collect();
                Some(StagedRegions::new(&self.ctx, image, &regions)?)
            }
            None => None,
        };
        let target = &self.heights[h].heights.image;
        let ao_maps = if self.pyramids_built {
            self.ao.maps_of(h)
        } else {
            // The first frame builds the AO from the painted field.
            Vec::new()
        };
        let mut report = PaintReport {
            strokes,
            splat_texels: staged.splat_rects.iter().map(TexelRect::texels).sum(),
            ..PaintReport::default()
        };
        let ao = &self.ao;
        report.gpu_ms = time_on_gpu(&self.ctx, |rec| {
            let regions = painter.record(rec, staged)?;
            record_paint_copies(
                rec,
                painter,
                &regions,
                target,
                splat_image.zip(splat_staged.as_ref()),
            )?;
            report.blended_texels = regions
                .iter()
                .map(|level| {
                    level
                        .iter()
                        .map(|r| u64::from(r[2]) * u64::from(r[3]))
                        .sum()
                })
                .collect();
            for &k in &ao_maps {
                for rect in &regions[0] {
                    if let Some(done) = ao.record_region(rec, k, *rect)? {
                        report.ao_texels += u64::from(done[2]) * u64::from(done[3]);
                    }
                }
            }
            Ok(())
        })?;
        Ok(report)
    }
}

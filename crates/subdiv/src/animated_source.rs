//! The viewer's source for an animated USD stage ([`AnimatedSource`]): each frame's time code
//! ([`FrameRequest::time`]) reads the cage at that time, and the tessellation follows it the
//! way a moving cage is tessellated frame by frame: the uniform layout kept
//! ([`StencilTessellator`]: the stencil table, or the slates), or the adaptive node's patches kept with its depths chosen again
//! ([`DynamicSubdivision::set_positions`]); a time code whose topology differs lays the cage
//! out again.

use subdiv_mesh::UsdStageReader;
use subdiv_rules::{Depth, Scheme};
use subdiv_stencil::StencilTessellator;
use subdiv_vk::viewer::{FrameRequest, FrameSource, Playback, SourceFrame};

use crate::{AdaptiveSource, DynamicSubdivision, Scene, SceneError, UniformSource};

/// The error type of [`FrameSource::frame`].
type FrameError = Box<dyn std::error::Error + Send + Sync>;

/// What follows the cage.
enum Moving {
    Uniform {
        tessellator: Box<StencilTessellator>,
        source: Box<UniformSource>,
    },
    Adaptive(Box<AdaptiveSource>),
}

/// A frame source that reads an animated stage at each frame's time code (see the module
/// notes); without a time code in the request it keeps the cage it has.
pub struct AnimatedSource {
    stage: UsdStageReader,
    /// The time code of the cage shown.
    shown: f64,
    moving: Moving,
}

impl AnimatedSource {
    /// The uniform `scheme` tessellation at `depth` of `stage`'s cage, first at time code
    /// `time`.
    pub fn uniform(
        stage: UsdStageReader,
        scheme: Scheme,
        depth: Depth,
        time: f64,
    ) -> Result<AnimatedSource, FrameError> {
        let cage = stage.read_at(Some(time))?.mesh;
        let tessellator = Box::new(StencilTessellator::new(&cage, scheme, depth)?);
        let scene = Scene::from_uniform(tessellator.surface().clone(), depth)?;
        Ok(AnimatedSource {
            stage,
            shown: time,
            moving: Moving::Uniform {
                tessellator,
                source: Box::new(UniformSource::new(scene)),
            },
        })
    }

    /// The adaptive tessellation of `node`, made for `stage`'s cage at time code `time`.
    pub fn adaptive(stage: UsdStageReader, node: DynamicSubdivision, time: f64) -> AnimatedSource {
        AnimatedSource {
            stage,
            shown: time,
            moving: Moving::Adaptive(Box::new(AdaptiveSource::new(node))),
        }
    }

    /// The uniform tessellation shown (`None` for the adaptive one).
    pub fn uniform_scene(&self) -> Option<&Scene> {
        match &self.moving {
            Moving::Uniform { source, .. } => Some(source.scene()),
            Moving::Adaptive(_) => None,
        }
    }

    /// The time code of the cage shown.
    pub fn time(&self) -> f64 {
        self.shown
    }

    /// Reads the cage at `time` and moves the tessellation to it.
    fn show(&mut self, time: f64) -> Result<(), FrameError> {
        let cage = self.stage.read_at(Some(time))?.mesh;
        match &mut self.moving {
            Moving::Uniform {
                tessellator,
                source,
            } => {
                let surface = tessellator.update(&cage)?.clone();
                let scene = Scene::from_uniform(surface, tessellator.depth())
                    .map_err(|e: SceneError| Box::new(e) as FrameError)?;
                source.set_scene(scene);
            }
            Moving::Adaptive(source) => source.set_cage(cage)?,
        }
        self.shown = time;
        Ok(())
    }
}

impl FrameSource for AnimatedSource {
    fn frame(&mut self, request: &FrameRequest) -> Result<SourceFrame<'_>, FrameError> {
        if let Some(t) = request.time
            && t != self.shown
        {
            self.show(t)?;
        }
        match &mut self.moving {
            Moving::Uniform { source, .. } => source.frame(request),
            Moving::Adaptive(source) => source.frame(request),
        }
    }
}

/// The viewer's playback of `stage`'s time range at its `timeCodesPerSecond`, from `time`
/// (`None`: from the start), running when `playing`; `None` when nothing on the stage moves.
pub fn stage_playback(
    stage: &UsdStageReader,
    time: Option<f64>,
    playing: bool,
) -> Result<Option<Playback>, FrameError> {
    let range = stage.time()?;
    let Some((start, end)) = range.range().filter(|_| range.is_animated()) else {
        return Ok(None);
    };
    Ok(Some(Playback {
        start,
        end,
        rate: range.time_codes_per_second,
        time: time.unwrap_or(start),
        playing,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{UsdReadOptions, read_obj};

    /// Moving to a time code tessellates the cage Pixar's USD reads at that time
    /// (`fixtures/usd/make_animated.py`), as a fresh scene of it does (the same faces; points
    /// and normals through the stencil table, to rounding); the vertex version moves.
    #[test]
    fn a_new_time_code_shows_the_stage_at_that_time() {
        let dir = subdiv_test_support::fixture("usd");
        let stage =
            UsdStageReader::open(dir.join("pawn_bend.usdc"), &UsdReadOptions::default()).unwrap();
        let playback = stage_playback(&stage, None, true).unwrap().unwrap();
        assert_eq!(
            (playback.start, playback.end, playback.rate),
            (1.0, 48.0, 24.0)
        );
        let mut source = AnimatedSource::uniform(stage, Scheme::CatmullClark, 2, 1.0).unwrap();
        for t in [13.0, 30.0, 1.0] {
            source.show(t).unwrap();
            assert_eq!(source.time(), t);
            let cage = read_obj(dir.join(format!("pawn_bend_t{t}.obj"))).unwrap();
            let want = Scene::uniform(&cage, Scheme::CatmullClark, 2).unwrap();
            let (got, want) = (source.uniform_scene().unwrap().surface(), want.surface());
            assert_eq!(got.face_indices(), want.face_indices(), "time {t}");
            let (lo, hi) = cage.bounds();
            let (d, a) = subdiv_test_support::max_deviation(
                (got.positions(), got.normals()),
                (want.positions(), want.normals()),
                (hi - lo).length(),
            );
            assert!(d < 1e-6 && a < 1e-4, "time {t}: {d} {a}");
        }
        let stage =
            UsdStageReader::open(dir.join("scene.usda"), &UsdReadOptions::default()).unwrap();
        assert_eq!(stage_playback(&stage, None, true).unwrap(), None);
    }
}

//! The node's frame-rate control: which controller runs ([`Control`]), the frame-time model
//! every mode keeps fitted, and what a frame did ([`FrameWork`]) for both.

use subdiv_depth::{
    Assignment, BudgetController, Choice, Class, FaceCost, FrameRateController, FrameTimeModel,
    FrameWork, PatchErrors, Sphere, capped_back_faces, face_errors, silhouette_depths,
};
use subdiv_mesh::Camera;
use subdiv_slate::Depth;
use subdiv_stitch::AdaptiveFrame;

/// How an adaptive node meets a target frame rate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Control {
    /// None: the depths are the geometric ones.
    #[default]
    Off,
    /// Predictive (the default when a target is set): each frame, the depths that minimise the
    /// estimated image error within the frame time the fitted model predicts
    /// ([`BudgetController`]).
    Budget,
    /// The paper's feedback controller: the depth cap, then a share of the patches, stepped
    /// towards the target ([`FrameRateController`]).
    Paper,
}

impl Control {
    /// Every mode, in the order a viewer cycles them.
    pub const ALL: [Control; 3] = [Control::Off, Control::Budget, Control::Paper];

    /// The mode's name (`off`, `budget`, `paper`).
    pub fn name(self) -> &'static str {
        match self {
            Control::Off => "off",
            Control::Budget => "budget",
            Control::Paper => "paper",
        }
    }
}

/// The running controller.
#[derive(Clone, Debug)]
pub(super) enum Controller {
    Off,
    Budget(BudgetController),
    Paper(FrameRateController),
}

impl Controller {
    pub(super) fn new(control: Control, target_fps: f32, max_depth: Depth) -> Controller {
        match control {
            Control::Off => Controller::Off,
            Control::Budget => Controller::Budget(BudgetController::new(target_fps)),
            Control::Paper => Controller::Paper(FrameRateController::new(target_fps, max_depth)),
        }
    }

    pub(super) fn mode(&self) -> Control {
        match self {
            Controller::Off => Control::Off,
            Controller::Budget(_) => Control::Budget,
            Controller::Paper(_) => Control::Paper,
        }
    }

    pub(super) fn target_fps(&self) -> Option<f32> {
        match self {
            Controller::Off => None,
            Controller::Budget(c) => Some(c.target_fps()),
            Controller::Paper(c) => Some(c.target_fps()),
        }
    }
}

/// What the frame-time model and the budget controller know of the last frame.
#[derive(Clone, Debug, Default)]
pub(super) struct LastFrame {
    /// Its work, as drawn.
    pub(super) work: Option<FrameWork>,
    /// The model's prediction for it (seconds).
    pub(super) predicted: Option<f64>,
    /// The budget controller's planned prediction for it (seconds).
    pub(super) planned: Option<f64>,
    /// It set up once-per-cage data (the pixel-error measurement), so its time says nothing
    /// of its work.
    pub(super) setup: bool,
}

/// Pixels covered, estimated from the projected discs of the faces that face the camera (their
/// bounding spheres: an overestimate by a factor about `π / 2`, the same every frame), capped
/// at the image: the fragment work of a frame as the model sees it.
pub(super) fn pixels(a: &Assignment, camera: &Camera) -> f64 {
    let image = f64::from(camera.width) * f64::from(camera.height);
    let sum: f64 = (0..a.depth.len())
        .filter(|&f| a.active[f] && a.class[f] != Class::Back)
        .map(|f| {
            let r = f64::from(a.radius[f]);
            (std::f64::consts::PI * r * r).min(image)
        })
        .sum();
    sum.min(image)
}

/// The work a frame did: its triangles, the points it tessellated and the vertices it
/// rewrote, and `pixels`.
pub(super) fn frame_work(g: &AdaptiveFrame, pixels: f64) -> FrameWork {
    let uploaded: u64 = g
        .dirty_vertices()
        .iter()
        .map(|r| u64::from(r.end - r.start))
        .sum();
    FrameWork {
        triangles: g.num_triangles() as f64,
        points: g.points_recomputed() as f64,
        uploaded: uploaded as f64,
        pixels,
    }
}

/// What the budget controller needs of the node for one frame.
pub(super) struct BudgetInputs<'a> {
    pub(super) camera: &'a Camera,
    pub(super) errors: &'a PatchErrors,
    pub(super) spheres: &'a [Sphere],
    pub(super) max_depth: Depth,
    pub(super) pixels: f64,
}

/// The budget controller's choice of `a.depth` (the geometric assignment on entry, whose
/// classes and back-face depths bound it); `min_depth` and `cached` give each face's least
/// depth and cached block depth. Returns the plan's predicted time (seconds).
pub(super) fn choose_budget(
    c: &mut BudgetController,
    model: &FrameTimeModel,
    inputs: &BudgetInputs<'_>,
    a: &mut Assignment,
    min_depth: &[Depth],
    cached: &[Option<Depth>],
) -> f64 {
    let errors = face_errors(
        inputs.camera,
        inputs.errors,
        inputs.spheres,
        a,
        inputs.max_depth,
    );
    let costs: Vec<FaceCost> = (0..a.depth.len())
        .map(|f| FaceCost {
            weight: inputs.errors.faces[f].shading.weight,
            cached: cached[f],
        })
        .collect();
    let first = silhouette_depths(
        inputs.camera,
        inputs.errors,
        inputs.spheres,
        a,
        inputs.max_depth,
    );
    let capped = capped_back_faces(inputs.camera, inputs.errors, inputs.spheres, a);
    let choice = Choice {
        errors: &errors,
        costs: &costs,
        assignment: a,
        capped: &capped,
        min_depth,
        first: &first,
        max_depth: inputs.max_depth,
        fixed: FrameWork {
            pixels: inputs.pixels,
            ..FrameWork::default()
        },
    };
    let mut depth = vec![0; a.depth.len()];
    let plan = c.choose(&choice, model, &mut depth);
    a.depth = depth;
    model.predict(&plan)
}

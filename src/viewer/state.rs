//! What the viewer's widgets edit: plain data, testable without a window. A change of the scene
//! or its material rebuilds the simulation (keeping the motion where the mesh is the same); a
//! change of [`Settings`] applies to the next frame.

use crate::compare::Compare;
use crate::constraints::{Orthotropic, SpringMaterial};
use crate::error::Result;
use crate::material::Model;
use crate::mesh::Diagonals;
use crate::scene::{self, SceneOptions, TetMode};
use crate::simulation::Backend;
use crate::solver::Settings;

/// The material of a scene, as the material picker offers it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialChoice {
    /// Springs of a cloth (Hookean or StVK), stiffness `k_s` (N/m).
    Spring(SpringMaterial),
    /// The orthotropic StVK membrane cloth (warp, weft, shear moduli in N/m, Poisson ratio).
    AnisoCloth,
    /// A 3D model on tetrahedra (Young's modulus in Pa, Poisson ratio).
    Solid(Model),
}

impl MaterialChoice {
    /// The materials a cloth scene takes.
    pub const CLOTH: [MaterialChoice; 3] = [
        MaterialChoice::Spring(SpringMaterial::Hookean),
        MaterialChoice::Spring(SpringMaterial::StVK),
        MaterialChoice::AnisoCloth,
    ];

    /// The materials a volumetric scene takes.
    pub const SOLID: [MaterialChoice; 5] = [
        MaterialChoice::Solid(Model::Linear),
        MaterialChoice::Solid(Model::StVK),
        MaterialChoice::Solid(Model::NeoHookean),
        MaterialChoice::Solid(Model::MooneyRivlin),
        MaterialChoice::Solid(Model::ArrudaBoyce),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            MaterialChoice::Spring(m) => m.name(),
            MaterialChoice::AnisoCloth => "aniso-cloth",
            MaterialChoice::Solid(m) => m.name(),
        }
    }
}

/// How the simulated surface is coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColorMode {
    /// The material colours (front red, back blue), lit.
    #[default]
    Shaded,
    /// Every element of one family drawn as its edges in the colour of its color group.
    ColorGroups,
    /// Mean relative stretch of the edges at each vertex, computed on the GPU.
    Strain,
    /// Each particle's share of the elastic energy of the elements it belongs to (J).
    Energy,
}

impl ColorMode {
    /// Every mode, in the order the picker lists them.
    pub const ALL: [ColorMode; 4] = [ColorMode::Shaded, ColorMode::ColorGroups, ColorMode::Strain, ColorMode::Energy];

    /// The picker's label.
    pub fn label(self) -> &'static str {
        match self {
            ColorMode::Shaded => "shaded",
            ColorMode::ColorGroups => "color groups",
            ColorMode::Strain => "strain",
            ColorMode::Energy => "elastic energy",
        }
    }
}

impl std::str::FromStr for ColorMode {
    type Err = crate::Error;
    fn from_str(s: &str) -> Result<Self> {
        crate::Error::lookup(
            "colour mode",
            s,
            &[
                ("shaded", ColorMode::Shaded),
                ("groups", ColorMode::ColorGroups),
                ("strain", ColorMode::Strain),
                ("energy", ColorMode::Energy),
            ],
        )
    }
}

/// The scene and material the user has chosen (everything that needs a rebuild).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneChoice {
    /// Index into [`scene::SCENES`].
    pub scene: usize,
    /// Whether the scene is volumetric (tetrahedra), which decides the materials it takes.
    pub solid: bool,
    /// The material.
    pub material: MaterialChoice,
    /// Spring stiffness `k_s` (N/m); also the default warp and weft of the membrane cloth.
    pub stiffness: f32,
    /// Membrane warp modulus `E_u` (N/m).
    pub warp: f64,
    /// Membrane weft modulus `E_v` (N/m).
    pub weft: f64,
    /// Membrane shear modulus `G` (N/m); `None` takes Huber's estimate.
    pub shear: Option<f64>,
    /// Young's modulus of the volumetric scenes (Pa).
    pub young: f64,
    /// Poisson's ratio (volumetric scenes and the membrane's `ν_uv`).
    pub poisson: f64,
    /// Dihedral bending stiffness `k_b` (N·m/rad), 0 switches it off; `None` takes the scene's
    /// own (the choice starts with the scene's own value filled in).
    pub bending: Option<f32>,
    /// Particles per side of a cloth, cells along a beam; `None` takes the scene's own.
    pub resolution: Option<u32>,
    /// How volumetric scenes are split into tetrahedra.
    pub tets: TetMode,
    /// How cloth grids are split into triangles.
    pub diagonals: Diagonals,
    /// Cloth self-collision on or off; `None` takes the scene's own (on for `cloth-drape` and
    /// `cloth-sphere`).
    pub self_collision: Option<bool>,
    /// Gravity on.
    pub gravity: bool,
}

impl SceneChoice {
    /// The choice for scene `name` with `opts` (the command line's), or an error naming the
    /// scene if it is unknown.
    pub fn new(name: &str, opts: &SceneOptions) -> Result<Self> {
        let index = scene::SCENES.iter().position(|s| *s == name).ok_or_else(|| crate::Error::UnknownName {
            what: "scene",
            given: name.to_string(),
            allowed: scene::SCENES.to_vec(),
        })?;
        let (solid, default_bending) = probe(name);
        let material = match (opts.solid, opts.membrane) {
            (Some(m), _) => MaterialChoice::Solid(m),
            (None, Some(_)) => MaterialChoice::AnisoCloth,
            (None, None) if solid => MaterialChoice::Solid(Model::NeoHookean),
            (None, None) => MaterialChoice::Spring(opts.material),
        };
        let k = opts.stiffness as f64;
        Ok(SceneChoice {
            scene: index,
            solid,
            material,
            stiffness: opts.stiffness,
            warp: opts.membrane.map_or(k, |m| m.warp),
            weft: opts.membrane.map_or(k, |m| m.weft),
            shear: opts.membrane.map(|m| m.shear),
            young: opts.young,
            poisson: opts.poisson,
            bending: opts.bending_stiffness.or(default_bending),
            resolution: opts.resolution,
            tets: opts.tets,
            diagonals: opts.diagonals,
            self_collision: opts.self_collision,
            gravity: opts.gravity,
        })
    }

    /// The scene's name.
    pub fn name(&self) -> &'static str {
        scene::SCENES.get(self.scene).copied().unwrap_or("cloth")
    }

    /// Switches to scene `index`, keeping the material where the new scene takes it and
    /// choosing the default of the other kind otherwise; the resolution goes back to the
    /// scene's own.
    pub fn set_scene(&mut self, index: usize) {
        if index == self.scene || index >= scene::SCENES.len() {
            return;
        }
        self.scene = index;
        let (solid, bending) = probe(self.name());
        self.solid = solid;
        self.bending = bending;
        self.resolution = None;
        self.self_collision = None;
        let fits = self.materials().contains(&self.material);
        if !fits {
            self.material = self.materials()[0];
            if self.solid {
                self.material = MaterialChoice::Solid(Model::NeoHookean);
            }
        }
    }

    /// Whether the current scene is a cloth grid (and so takes [`Diagonals`]).
    pub fn is_cloth(&self) -> bool {
        scene::is_cloth(self.name())
    }

    /// Whether the cloth collides with itself: the choice, else the scene's own.
    pub fn self_collides(&self) -> bool {
        self.self_collision.unwrap_or(scene::self_collides_by_default(self.name()))
    }

    /// The materials the current scene takes.
    pub fn materials(&self) -> &'static [MaterialChoice] {
        if self.solid { &MaterialChoice::SOLID } else { &MaterialChoice::CLOTH }
    }

    /// The scene options of this choice (validated when the scene is built).
    pub fn options(&self) -> Result<SceneOptions> {
        let mut o = SceneOptions {
            resolution: self.resolution,
            stiffness: self.stiffness,
            bending_stiffness: self.bending,
            gravity: self.gravity,
            young: self.young,
            poisson: self.poisson,
            tets: if self.solid { self.tets } else { TetMode::Volume },
            diagonals: if self.is_cloth() { self.diagonals } else { Diagonals::Uniform },
            self_collision: self.self_collision.filter(|_| self.is_cloth()),
            ..SceneOptions::default()
        };
        match self.material {
            MaterialChoice::Spring(m) => o.material = m,
            MaterialChoice::AnisoCloth => {
                o.membrane = Some(Orthotropic::new(self.warp, self.weft, self.shear, self.poisson)?);
            }
            MaterialChoice::Solid(m) => o.solid = Some(m),
        }
        Ok(o)
    }
}

/// Whether scene `name` is volumetric (its default build has tetrahedra), and its default
/// bending stiffness (N·m/rad; `None` for a scene that cannot have bending or is unknown).
pub fn probe(name: &str) -> (bool, Option<f32>) {
    match scene::build(name, &SceneOptions::default()) {
        Ok(s) if s.tets.is_some() => (true, None),
        Ok(s) => (false, Some(s.bends.as_ref().and_then(|b| b.elements.first()).map_or(0.0, |b| b.k))),
        Err(_) => (false, None),
    }
}

/// One-shot requests from the buttons, taken by the session at the start of the next frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Requests {
    /// Advance one frame while paused.
    pub step: bool,
    /// Back to the scene's initial state.
    pub reset: bool,
    /// Back to the camera that frames the scene.
    pub reset_camera: bool,
}

/// The grab's spring stiffness by default (N/m): a hanging cloth's particle trails the cursor by
/// a few centimetres and a hard pull stretches the cloth.
pub const DEFAULT_GRAB_STIFFNESS: f32 = 300.0;

/// Everything the panels edit. The session reads it once per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerState {
    /// Compare mode: a second run beside the first differing in this setting (`None`: one run).
    pub compare: Option<Compare>,
    /// Scene and material (changes rebuild the simulation).
    pub choice: SceneChoice,
    /// Solver settings for the next frame.
    pub settings: Settings,
    /// Where the solver runs.
    pub backend: Backend,
    /// Whether the simulation is paused.
    pub paused: bool,
    /// Surface edges drawn over the surface.
    pub wireframe: bool,
    /// How the surface is coloured.
    pub color_mode: ColorMode,
    /// The family whose color groups are shown (index in solve order among the scene's families).
    pub group_family: usize,
    /// Relative stretch drawn red in the strain mode.
    pub strain_scale: f32,
    /// The grab's spring stiffness (N/m; [`crate::solver::Pull`]); 0 pins the grabbed particle.
    pub grab_stiffness: f32,
    /// Button requests.
    pub requests: Requests,
    /// The last error to show (a refused parameter, a failed rebuild).
    pub error: Option<String>,
}

impl ViewerState {
    /// A keyboard shortcut: space pauses or runs, `s` steps one frame (pausing first), `r`
    /// resets the scene, `c` turns compare mode (energy-aware off | on) on or off. Returns
    /// whether `key` is one.
    pub fn shortcut(&mut self, key: char) -> bool {
        match key.to_ascii_lowercase() {
            ' ' => self.paused = !self.paused,
            's' => {
                self.paused = true;
                self.requests.step = true;
            }
            'r' => self.requests.reset = true,
            'c' => self.compare = if self.compare.is_some() { None } else { Some(Compare::EnergyAware) },
            _ => return false,
        }
        true
    }

    /// The state for a scene choice, settings and backend.
    pub fn new(choice: SceneChoice, settings: Settings, backend: Backend) -> Self {
        ViewerState {
            compare: None,
            choice,
            settings,
            backend,
            paused: false,
            wireframe: false,
            color_mode: ColorMode::Shaded,
            group_family: 0,
            strain_scale: 0.05,
            grab_stiffness: DEFAULT_GRAB_STIFFNESS,
            requests: Requests::default(),
            error: None,
        }
    }

    /// The settings to run the next frame with, or the reason they are refused.
    pub fn frame_settings(&self) -> Result<Settings> {
        self.settings.validate()?;
        Ok(self.settings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn self_collision_follows_the_scene_until_chosen() {
        let mut c = SceneChoice::new("cloth-drape", &SceneOptions::default()).unwrap();
        assert!(c.self_collides());
        c.self_collision = Some(false);
        assert!(scene::build(c.name(), &c.options().unwrap()).unwrap().self_collision.is_none());
        c.set_scene(0);
        assert!(!c.self_collides(), "another scene starts from its own default");
        let beam = scene::SCENES.iter().position(|s| *s == "beam").unwrap();
        c.set_scene(beam);
        c.self_collision = Some(true);
        assert_eq!(c.options().unwrap().self_collision, None, "solids take none");
    }

    #[test]
    fn every_scene_has_a_choice_whose_options_build() {
        for name in scene::SCENES {
            let c = SceneChoice::new(name, &SceneOptions::default()).unwrap();
            assert_eq!(c.name(), name);
            let s = scene::build(name, &c.options().unwrap()).unwrap();
            assert_eq!(s.tets.is_some(), c.solid, "{name}");
        }
    }

    #[test]
    fn switching_scene_kind_picks_a_material_it_takes() {
        let mut c = SceneChoice::new("cloth", &SceneOptions::default()).unwrap();
        let beam = scene::SCENES.iter().position(|s| *s == "beam").unwrap();
        c.set_scene(beam);
        assert_eq!(c.material, MaterialChoice::Solid(Model::NeoHookean));
        c.set_scene(0);
        assert!(matches!(c.material, MaterialChoice::Spring(_)));
        assert!(SceneChoice::new("drape", &SceneOptions::default()).is_err());
    }
}

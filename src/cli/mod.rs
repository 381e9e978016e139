//! Command-line arguments shared by the subcommands.

/// `println!` for the commands' output: ends the program quietly when standard output is closed
/// (piped into `head`, say) instead of panicking ([`write_out`]).
macro_rules! say {
    ($($t:tt)*) => { $crate::cli::write_out(format_args!($($t)*), true) };
}

/// `print!` for the commands' output, as [`say!`].
macro_rules! put {
    ($($t:tt)*) => { $crate::cli::write_out(format_args!($($t)*), false) };
}

pub mod bench;
pub mod render;
pub mod report;
pub mod scene_file;
pub mod simulate;
pub mod view;

use std::str::FromStr;

use clap::{Args, Parser, Subcommand};
use eapbd::constraints::{Form, Orthotropic, SpringMaterial};
use eapbd::material::Model;
use eapbd::mesh::Diagonals;
use eapbd::scene::{Body, SceneOptions, TetMode};
use eapbd::solver::{EnergyAware, Method, Settings};

/// Energy-aware position-based dynamics for elastic models. Without a subcommand, opens the
/// interactive viewer on the hanging cloth.
#[derive(Parser, Debug)]
#[command(name = "eapbd", version, about, args_override_self = true)]
pub struct Cli {
    /// What to do (default: the viewer on the cloth).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Open the interactive viewer (a window with controls, statistics and plots).
    View(view::ViewArgs),
    /// Run a scene headless (CPU solver unless --backend gpu) and print per-frame residual,
    /// stretch and energies.
    Simulate(simulate::SimulateArgs),
    /// Simulate headless and write frames as PNG images.
    Render(render::RenderArgs),
    /// Studies written as CSV, Markdown and PNG plots.
    Report(report::ReportArgs),
    /// Time the solver and the mesh coloring.
    Bench(bench::BenchArgs),
}

/// Parses a value through its `FromStr`, whose error lists the allowed names.
pub(crate) fn named<T: FromStr<Err = eapbd::Error>>(s: &str) -> Result<T, eapbd::Error> {
    s.parse()
}

/// `on` or `off`.
fn on_off(s: &str) -> Result<bool, eapbd::Error> {
    eapbd::Error::lookup("switch", s, &[("on", true), ("off", false)])
}

/// A material name from the command line: a spring model, the anisotropic continuum cloth or a
/// 3D model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialArg {
    /// Springs (cloth scenes).
    Spring(SpringMaterial),
    /// The orthotropic StVK membrane (cloth scenes).
    AnisoCloth,
    /// Tetrahedra (volumetric scenes).
    Solid(Model),
}

/// The name of [`MaterialArg::AnisoCloth`].
const ANISO_CLOTH: &str = "aniso-cloth";

fn material(s: &str) -> Result<MaterialArg, eapbd::Error> {
    if let Ok(m) = s.parse::<SpringMaterial>() {
        return Ok(MaterialArg::Spring(m));
    }
    if s == ANISO_CLOTH {
        return Ok(MaterialArg::AnisoCloth);
    }
    s.parse::<Model>().map(MaterialArg::Solid).map_err(|_| eapbd::Error::UnknownName {
        what: "material",
        given: s.to_string(),
        allowed: SpringMaterial::NAMES.into_iter().chain([ANISO_CLOTH]).chain(Model::ALL.map(Model::name)).collect(),
    })
}

/// Scene and solver options common to every command that runs a scene.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// Scene: cloth, cloth-paper, cloth-sphere, cloth-free, cloth-drape, beam, cube, bunny or
    /// bunny-paper.
    #[arg(long, default_value = "cloth-paper")]
    pub scene: String,
    /// bunny, bunny-paper: simulate this OBJ surface instead of the bunny (scaled to 0.3 m tall;
    /// closed for tetrahedral bodies), or a TetGen mesh given as PATH.node or PATH.ele.
    #[arg(long)]
    pub mesh: Option<std::path::PathBuf>,
    /// bunny, bunny-paper: springs (surface spring network), centroid-tets (the paper's surface
    /// triangles with the centroid) or volume (a tetrahedral lattice with the surface embedded).
    /// Default: volume for bunny, springs for bunny-paper.
    #[arg(long, value_parser = named::<Body>)]
    pub body: Option<Body>,
    /// volume bodies: lattice cells along the longest side (default 16).
    #[arg(long)]
    pub lattice: Option<u32>,
    /// Particles per side of a cloth (default 41, at most 2048); cells along the beam (10, at
    /// most 414) or along each side of the cube (4, at most 140).
    #[arg(long)]
    pub resolution: Option<u32>,
    /// Small-strain spring stiffness k_s (N/m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0e4)]
    pub stiffness: f32,
    /// Material: hookean, stvk-spring or aniso-cloth (cloth scenes); linear, stvk, neo-hookean,
    /// mooney-rivlin or arruda-boyce (beam, cube and the bunny's tetrahedral bodies; default
    /// neo-hookean). The bunny's springs body takes hookean or stvk-spring.
    #[arg(long, value_parser = material)]
    pub material: Option<MaterialArg>,
    /// Young's modulus of the volumetric scenes (Pa).
    #[arg(long, allow_negative_numbers = true, default_value_t = 2.0e6)]
    pub young: f64,
    /// Poisson's ratio of the volumetric scenes, and ν_uv of aniso-cloth.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.3)]
    pub poisson: f64,
    /// Tetrahedra of beam and cube: volume (a volumetric mesh) or centroid (the paper's surface
    /// triangles paired with the centroid).
    #[arg(long, default_value = "volume", value_parser = named::<TetMode>)]
    pub tets: TetMode,
    /// Cloth scenes: every quad split along the same diagonal (uniform) or along alternating
    /// ones in a checkerboard (alternating: the PositionBasedDynamics library's cloth mesh).
    #[arg(long, default_value = "uniform", value_parser = named::<Diagonals>)]
    pub diagonals: Diagonals,
    /// Cloth scenes: self-collision on or off (default: on for cloth-drape and cloth-sphere,
    /// off for the others).
    #[arg(long, value_parser = on_off)]
    pub self_collision: Option<bool>,
    /// Cloth scenes: the distance self-collision keeps between particles (m; default: 1.2
    /// times the grid's spacing, 1.2 m / (resolution − 1); at most 1.5 times).
    #[arg(long, allow_negative_numbers = true)]
    pub thickness: Option<f32>,
    /// aniso-cloth: warp modulus E_u along x (N/m; default: --stiffness).
    #[arg(long, allow_negative_numbers = true)]
    pub warp: Option<f64>,
    /// aniso-cloth: weft modulus E_v along z (N/m; default: --stiffness).
    #[arg(long, allow_negative_numbers = true)]
    pub weft: Option<f64>,
    /// aniso-cloth: shear modulus G (N/m; default √(E_u E_v)/(2(1 + ν))).
    #[arg(long, allow_negative_numbers = true)]
    pub shear: Option<f64>,
    /// Dihedral bending stiffness k_b (N·m/rad); 0 disables. Default: 1e-3 for cloth,
    /// cloth-sphere, cloth-free, cloth-drape and the bunny's springs body, 0 for cloth-paper.
    #[arg(long, allow_negative_numbers = true)]
    pub bending_stiffness: Option<f32>,
    /// Frame time step (s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0 / 60.0)]
    pub dt: f32,
    /// Substeps per frame.
    #[arg(long, default_value_t = 1)]
    pub substeps: u32,
    /// Constraint iterations per substep (default 30; the paper's 15 for bunny-paper).
    #[arg(long)]
    pub iterations: Option<u32>,
    /// Projection form: compliant (standard XPBD) or energy (the paper's C = E).
    #[arg(long, default_value = "compliant", value_parser = named::<Form>)]
    pub form: Form,
    /// Iteration: gauss-seidel or jacobi.
    #[arg(long, default_value = "gauss-seidel", value_parser = named::<Method>)]
    pub solver: Method,
    /// Jacobi relaxation ω (0 < ω < 2).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub jacobi_omega: f32,
    /// Physical velocity damping β_v (1/s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub damping: f32,
    /// XPBD constraint damping β (s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub constraint_damping: f32,
    /// Compliance α of the energy form.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0e-5)]
    pub energy_compliance: f32,
    /// Energy-aware Gauss-Seidel: off, local (the paper's per-constraint reading), global (one
    /// balance of the iterate's energy per substep) or project (the energy-momentum projection
    /// of the honest energy after every frame; "on" means project).
    #[arg(long, default_value = "off", value_parser = named::<EnergyAware>)]
    pub energy_aware: EnergyAware,
    /// Successive over-relaxation ω (every Δλ times ω; 1 = plain, 1.5 is the usual baseline).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub sor: f32,
    /// CPU threads that split the color groups (Jacobi: the constraints) and the particle passes
    /// (0 = every core, 1 = single-threaded, at most one per core; small groups run on one thread,
    /// and the result does not depend on the count).
    #[arg(long, default_value_t = 0)]
    pub threads: u32,
    /// Switch gravity off.
    #[arg(long)]
    pub no_gravity: bool,
    /// Read scene and solver flags from this TOML file (flags on the command line override it;
    /// examples in assets/scenes/).
    #[arg(long)]
    pub scene_file: Option<std::path::PathBuf>,
    /// Write the scene and solver flags of this run to this TOML file, for --scene-file.
    #[arg(long)]
    pub save_scene: Option<std::path::PathBuf>,
}

impl SceneArgs {
    /// The scene options these arguments select.
    pub fn scene_options(&self) -> eapbd::Result<SceneOptions> {
        let solid_scene = eapbd::scene::uses_tets(&self.scene, self.body);
        let (material, solid) = match self.material {
            Some(MaterialArg::Spring(m)) if solid_scene => {
                return Err(eapbd::Error::param(
                    "--material",
                    m.name(),
                    "is a spring model; tetrahedral bodies take linear, stvk, neo-hookean, mooney-rivlin or arruda-boyce",
                ));
            }
            Some(MaterialArg::Spring(m)) => (m, None),
            Some(MaterialArg::Solid(m)) => (SpringMaterial::Hookean, Some(m)),
            Some(MaterialArg::AnisoCloth) | None => (SpringMaterial::Hookean, None),
        };
        let aniso = self.material == Some(MaterialArg::AnisoCloth);
        if !aniso
            && let Some((flag, _)) = [("--warp", self.warp), ("--weft", self.weft), ("--shear", self.shear)]
                .into_iter()
                .find(|(_, v)| v.is_some())
        {
            return Err(eapbd::Error::param(flag, "given", "applies only to --material aniso-cloth"));
        }
        let membrane = if aniso {
            let k = self.stiffness as f64;
            Some(Orthotropic::new(self.warp.unwrap_or(k), self.weft.unwrap_or(k), self.shear, self.poisson)?)
        } else {
            None
        };
        Ok(SceneOptions {
            resolution: self.resolution,
            stiffness: self.stiffness,
            material,
            bending_stiffness: self.bending_stiffness,
            gravity: !self.no_gravity,
            solid,
            young: self.young,
            poisson: self.poisson,
            membrane,
            tets: self.tets,
            body: self.body,
            lattice: self.lattice,
            diagonals: self.diagonals,
            self_collision: self.self_collision,
            thickness: self.thickness,
        })
    }

    /// Writes `--save-scene` if given: the scene flags among `matches` (the subcommand's).
    pub fn save(&self, matches: &clap::ArgMatches) -> anyhow::Result<()> {
        let Some(path) = &self.save_scene else { return Ok(()) };
        use clap::Args as _;
        let cmd = SceneArgs::augment_args(clap::Command::new("scene"));
        let scene_ids: Vec<String> = cmd.get_arguments().map(|a| a.get_id().to_string()).collect();
        let skip: Vec<&str> = matches
            .ids()
            .map(|id| id.as_str())
            .filter(|id| !scene_ids.iter().any(|s| s == id) || matches!(*id, "save_scene" | "scene_file"))
            .collect();
        scene_file::write(path, matches, &skip)?;
        say!("wrote {}", path.display());
        Ok(())
    }

    /// The scene these arguments select (reading `--mesh` if given).
    pub fn build_scene(&self) -> eapbd::Result<eapbd::scene::Scene> {
        let opts = self.scene_options()?;
        let tetgen = |p: &std::path::Path| p.extension().is_some_and(|e| e == "node" || e == "ele");
        match &self.mesh {
            Some(path) if tetgen(path) => {
                eapbd::scene::build_with_tets(&self.scene, &opts, eapbd::mesh::load_tetgen(path)?)
            }
            Some(path) => eapbd::scene::build_with_surface(&self.scene, &opts, eapbd::mesh::load_obj(path)?),
            None => eapbd::scene::build(&self.scene, &opts),
        }
    }

    /// The solver settings these arguments select, validated.
    pub fn settings(&self) -> eapbd::Result<Settings> {
        let s = Settings {
            dt: self.dt,
            substeps: self.substeps,
            iterations: self.iterations.unwrap_or_else(|| eapbd::scene::default_iterations(&self.scene)),
            form: self.form,
            method: self.solver,
            jacobi_omega: self.jacobi_omega,
            damping: self.damping,
            constraint_damping: self.constraint_damping,
            energy_compliance: self.energy_compliance,
            energy_aware: self.energy_aware,
            sor: self.sor,
            threads: self.threads,
            pull: None,
        };
        s.validate()?;
        Ok(s)
    }
}

/// Warns on standard error where `f32` positions cannot resolve a substep's motion under
/// gravity (`eapbd::solver::precision`), and where the body's material has no lower bound on its
/// energy (`eapbd::material::Elastic::caveat`).
pub fn warn_about(scene: &eapbd::scene::Scene, s: &Settings) {
    if let Some(u) = eapbd::solver::precision::unresolved_substep(scene, s) {
        eprintln!("warning: {u}");
    }
    if let Some(c) = scene.tets.as_ref().and_then(|t| t.params.elastic.caveat()) {
        eprintln!("warning: {c}");
    }
}

/// Writes `args` (and a newline when `line`) to standard output. A reader that went away (a
/// broken pipe) ends the program with success, as the usual command-line tools do; any other
/// write error ends it with a message and status 1.
pub fn write_out(args: std::fmt::Arguments<'_>, line: bool) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let written = out.write_fmt(args).and_then(|()| if line { out.write_all(b"\n") } else { Ok(()) });
    match written.and_then(|()| out.flush()) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => {
            eprintln!("Error: cannot write to standard output: {e}");
            std::process::exit(1);
        }
    }
}

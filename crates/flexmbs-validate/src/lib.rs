//! Validation cases of flexmbs, run by `flexmbs validate`. Each case computes its quantities with
//! flexmbs, compares them with a reference from outside flexmbs's formulation (analytic solution,
//! published value, CalculiX run) and writes `validation/<case>/result.json` (contract in
//! `../shared/reference/benchmarks.md`).
#![warn(missing_docs)]

pub mod cantilever_plate;
pub mod cantilever_static;
pub mod cantilever_transient;
pub mod complex_beam_ccx;
pub mod complex_beam_frequencies;
pub mod elastica;
pub mod fe_cantilever_modes;
pub mod point_mass_on_beam;
pub mod point_mass_on_beam_convergence;
pub mod point_mass_on_beam_figures;
pub mod point_mass_on_beam_full_fe;
pub mod result;
pub mod rotating_beam;
pub mod rotating_beam_reference;
pub mod rotating_beam_superelement;
pub mod slider_crank_2d;
pub mod slider_crank_3d;
pub mod slider_crank_3d_model;
pub mod slider_crank_3d_reference;
pub mod slider_crank_reference;
pub mod slider_crank_superelement;
pub mod sliding_balls;
pub mod sliding_balls_arc;
pub mod sliding_balls_reference;
pub mod spinning_beam;

pub use result::ValidationResult;
use std::path::Path;

/// A validation case.
pub struct Case {
    /// Name (folder under `validation/`).
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Runs the case, writing plots and tables into the given folder.
    pub run: fn(&Path, bool) -> anyhow::Result<ValidationResult>,
}

/// All cases.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "fe_cantilever_modes",
            description: "steel cantilever 1 m x 20 mm x 20 mm: bending, torsion, axial frequencies vs beam theory",
            run: fe_cantilever_modes::run,
        },
        Case {
            name: "complex_beam_frequencies",
            description: "seed 000 §5.1: FFR complex beam (built-in mesh and CalculiX export), simulated modal frequencies vs the modal analysis",
            run: complex_beam_frequencies::run,
        },
        Case {
            name: "slider_crank_2d",
            description: "seed 001 §5.1: flexible slider-crank, rod as 10 and 2 superelements and as one FFR body vs a corotational-beam reference",
            run: slider_crank_2d::run,
        },
        Case {
            name: "slider_crank_3d",
            description: "seed 001 §5.1: spatial flexible slider-crank (crank axis offset 0.1 m), rod as 10 and 2 superelements and one FFR body vs a discrete-elastic-rod reference; rigid kinematics vs closed form; planar limit vs slider_crank_2d (1 revolution; SLIDER_CRANK_3D_REVOLUTIONS=4 for 4)",
            run: slider_crank_3d::run,
        },
        Case {
            name: "spinning_beam",
            description: "seed 001 §5.1 (Cardona & Geradin), consistent variant: beam on a spherical joint spun up to 0.1 rad/s by a torque, vertical tip impulse at 25.2 s, 2 superelements to 50 s; angular momentum, energy, rigid-body angular velocity",
            run: spinning_beam::run,
        },
        Case {
            name: "rotating_beam",
            description: "seed 001 §5.2: rotating tube, FFR body with and without geometric stiffening and chains of 1, 2, 3, 10 superelements vs a nonlinear finite-segment reference",
            run: rotating_beam::run,
        },
        Case {
            name: "cantilever_static",
            description: "seed 001 §5.1/5.3: cantilever tube under a vertical tip force, chains of superelements vs the elastica",
            run: cantilever_static::run,
        },
        Case {
            name: "cantilever_plate",
            description: "seed 001 §8.4: plate 10 x 1 x 0.1 m under two vertical tip forces, 10 superelements with 4 interface points from an FE body file vs geometrically nonlinear CalculiX (C3D20R)",
            run: cantilever_plate::run,
        },
        Case {
            name: "cantilever_transient",
            description: "seed 001 §5.2: cantilever tube under a ramped tip force, 1/3/10 superelements, floating frame at the centre of mass or at the interface (qualitative)",
            run: cantilever_transient::run,
        },
        Case {
            name: "point_mass_on_beam",
            description: "seed 000 §5.2: a point mass hits a soft FFR cantilever (hex20 25x5x5): 2D neutral NURBS contour and FlexibleBand, Newton impact and penalty, Moreau fixed and step-size controlled; energy laws and mode convergence",
            run: point_mass_on_beam::run,
        },
        Case {
            name: "sliding_balls",
            description: "seed 000 §5.3: a ball kept on a soft FFR cantilever's neutral axis (bilateral guide, rotations follow), 10/20/40/100 modes vs a corotational-beam reference, 0.5 s (5 s with SLIDING_BALLS_T_END=5); energy, no velocity jumps, mode convergence",
            run: sliding_balls::run,
        },
    ]
}

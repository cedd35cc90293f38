//! A chain of N links joined by revolute joints (axis z), hinged to ground at the origin and
//! laid out along x, falling under gravity -y: six-mode FFR links (clamped at their hinge, six
//! lumped nodes) or rigid links. Shared by `tests/algebra.rs` and `benches/chain_steps.rs`.
#![allow(dead_code)]

use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam as FfrRot};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

/// Link length (m).
pub const LINK_LENGTH: f64 = 0.5;
const NODES: usize = 6;

/// Kind of the links.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Link {
    /// Six-mode FFR link, quaternion floating frame (nu = 12).
    Flexible,
    /// Rigid link, quaternion (nu = 6).
    Rigid,
}

/// Six-mode FFR body: nodes along x, modes `x^2, x^3, x^4` in y and z (zero at the hinge),
/// lumped masses and rotary inertias.
fn flexible_link() -> FfrElement {
    let dx = LINK_LENGTH / (NODES - 1) as f64;
    let nodes: Vec<[f64; 3]> = (0..NODES).map(|i| [dx * i as f64, 0.0, 0.0]).collect();
    let masses = vec![0.2; NODES];
    let nf = 6;
    let modes = faer::Mat::from_fn(3 * NODES, nf, |r, c| {
        let (node, dir) = (r / 3, r % 3);
        if dir == 1 + c % 2 {
            (dx * node as f64 / LINK_LENGTH).powi(2 + (c / 2) as i32)
        } else {
            0.0
        }
    });
    let k = faer::Mat::from_fn(
        nf,
        nf,
        |i, j| {
            if i == j {
                2e3 * (i + 1) as f64
            } else {
                0.0
            }
        },
    );
    let inv = FfrInvariants::from_lumped(&nodes, &masses, modes.as_ref()).unwrap();
    let mut body = FfrBody::new(
        inv,
        FfrRot::Quaternion,
        &nodes,
        modes.as_ref(),
        None,
        k.as_ref(),
    )
    .unwrap();
    // rotary inertia of the nodes: without it the point masses on the x axis give no inertia
    // about x and the mass matrix is singular
    let j = flexmbs_core::ffr::diagonal_inertia(Vector3::new(2e-4, 1e-4, 1e-4));
    body.set_rotary_inertia(&vec![j; NODES]).unwrap();
    FfrElement::new(body)
}

/// The chain model and its initial state (assembled, at rest). With `loads`, a spring-damper
/// between the tips of links 0 and 2 (if `n >= 3`) and a force on the last tip, given in these
/// coordinates (`Frame`: a follower force).
pub fn chain(n: usize, link: Link, loads: Option<LoadCoordinates>) -> (Model, State) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let z = Matrix3::identity();
    let mut prev = spec.add_ground_frame("hinge", Vector3::zeros(), z);
    let mut bodies = Vec::new();
    let mut tips = Vec::new();
    for i in 0..n {
        let name = format!("link{i}");
        let (b, root, tip) = match link {
            Link::Flexible => {
                let b = spec.add_body(&name, flexible_link());
                let root = spec.add_frame(&format!("{name}_root"), b, Vector3::zeros(), z);
                let tip_pos = Vector3::new(LINK_LENGTH, 0.0, 0.0);
                let tip = spec.add_node_frame(&format!("{name}_tip"), b, NODES - 1, tip_pos);
                (b, root, tip)
            }
            Link::Rigid => {
                let (m, l) = (1.2, LINK_LENGTH);
                let inertia =
                    Matrix3::from_diagonal(&Vector3::new(1e-3, m * l * l / 12.0, m * l * l / 12.0));
                let body = RigidBody::new(m, inertia).with_rotation(RotationParam::Quaternion);
                let b = spec.add_body(&name, body);
                let half = Vector3::new(0.5 * l, 0.0, 0.0);
                let root = spec.add_frame(&format!("{name}_root"), b, -half, z);
                let tip = spec.add_frame(&format!("{name}_tip"), b, half, z);
                (b, root, tip)
            }
        };
        spec.add_joint(Joint::revolute(&format!("joint{i}"), prev, root));
        prev = tip;
        bodies.push(b);
        tips.push(tip);
    }
    if let Some(coordinates) = loads {
        if n >= 3 {
            spec.add_load(Load::SpringDamper {
                frame_a: tips[0],
                frame_b: tips[2],
                stiffness: 50.0,
                damping: 0.5,
                free_length: 0.8,
            });
        }
        spec.add_load(Load::Force {
            frame: tips[n - 1],
            vector: Vector3::new(0.0, 2.0, 1.0),
            time: TimeFunction::Constant(1.0),
            coordinates,
        });
    }
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, &b) in bodies.iter().enumerate() {
        let x = match link {
            Link::Flexible => i as f64 * LINK_LENGTH,
            Link::Rigid => (i as f64 + 0.5) * LINK_LENGTH,
        };
        model.set_body_pose(&mut s, b, Vector3::new(x, 0.0, 0.0), z);
    }
    (model, s)
}

//! Phase timing and resident memory of the sparse eigen path on the 60k-DOF hex20 bench model
//! (`benches/modal_60k.toml`): `cargo run --release -p flexmbs-fe --example modal_probe`.
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::{lowest_modes, EigenEvent, EigenOptions};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::box_mesh;
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{ElementKind, Material, UnitSystem};
use std::time::Instant;

fn rss() -> String {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let get = |k: &str| {
        s.lines()
            .find_map(|l| l.strip_prefix(k))
            .map(|v| v.trim().to_string())
            .unwrap_or_default()
    };
    format!("rss {} hwm {}", get("VmRSS:"), get("VmHWM:"))
}

fn main() {
    let t0 = Instant::now();
    let div: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("divisions"))
        .collect();
    let div = if div.len() == 3 {
        [div[0], div[1], div[2]]
    } else {
        [110, 6, 6]
    };
    let mat = Material {
        e: 210e9,
        nu: 0.3,
        rho: 7850.0,
    };
    let mesh = box_mesh(
        [1.1, 0.1, 0.1],
        div,
        ElementKind::Hex20,
        mat,
        UnitSystem::Si,
    )
    .expect("mesh");
    let bc = BoundaryConditions {
        fixed: mesh.node_set("xmin").expect("xmin").to_vec(),
        rigid: Vec::new(),
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Consistent, &mut |_, _| {}).expect("asm");
    eprintln!(
        "{:7.3} s assembled n = {}, {}",
        t0.elapsed().as_secs_f64(),
        sys.len(),
        rss()
    );
    let tr = |a: &flexmbs_fe::SparseMatrix| -> f64 {
        (0..a.ncols())
            .map(|j| {
                let r = a.row_idx_of_col_raw(j);
                r.iter()
                    .position(|&i| i == j)
                    .map_or(0.0, |p| a.val_of_col(j)[p])
            })
            .sum()
    };
    eprintln!("sigma0 = {:e}", -1e-5 * tr(&sys.k) / tr(&sys.m));
    let opts = EigenOptions {
        n_modes: 20,
        max_basis: std::env::var("MAXB")
            .ok()
            .map_or(0, |v| v.parse().expect("MAXB")),
        block_size: std::env::var("BLOCK")
            .ok()
            .map_or(8, |v| v.parse().expect("BLOCK")),
        ..EigenOptions::default()
    };
    let mut last = String::new();
    let mut iterations = 0usize;
    let sol = lowest_modes(&sys.k, &sys.m, &opts, &mut |e| {
        let s = match e {
            EigenEvent::Iteration {
                basis, converged, ..
            } => {
                iterations += 1;
                if std::env::var_os("ALL").is_some() {
                    eprintln!(
                        "{:7.3} s basis {basis} converged {converged}",
                        t0.elapsed().as_secs_f64()
                    );
                }
                "iteration".to_string()
            }
            e => format!("{e:?}"),
        };
        if s != "iteration" || last != "iteration" {
            eprintln!("{:7.3} s {s} {}", t0.elapsed().as_secs_f64(), rss());
        }
        last = s;
    })
    .expect("eigen");
    eprintln!(
        "{:7.3} s done {} ({iterations} block steps)",
        t0.elapsed().as_secs_f64(),
        rss()
    );
    let hz: Vec<String> = sol
        .omega2
        .iter()
        .map(|w| format!("{:.7e}", w.sqrt() / (2.0 * std::f64::consts::PI)))
        .collect();
    println!("{}", hz.join(" "));
    println!("sturm {:?}", sol.sturm);
}

#[path = "../tests/common/mod.rs"]
mod common;
use flexmbs_core::integrator::*;
use flexmbs_core::*;
fn main() {
    for (rho, h) in [(1.0, 2.5e-4), (1.0, 1e-3), (0.9, 2.5e-4), (0.9, 1e-3)] {
        let p = common::Pendulum::new(RotationParam::Cardan);
        let ga = GenAlpha::new(GenAlphaSettings {
            rho_inf: rho,
            ..Default::default()
        })
        .unwrap();
        let mut s = p.state(std::f64::consts::FRAC_PI_2);
        let mut ws = Workspace::new(&p.model);
        ga.initialize(&p.model, &mut s, &mut ws).unwrap();
        let e0 = integrator::monitor(&p.model, &s, &mut ws).0.total();
        let mut out = vec![];
        let mut gd: f64 = 0.0;
        for k in 0..40000 {
            let st = match ga.step(&p.model, &mut s, &mut ws, h) {
                Ok(s) => s,
                Err(e) => {
                    println!("{e}");
                    break;
                }
            };
            gd = gd.max(st.g_dot_max);
            if k % 4000 == 0 {
                out.push(format!(
                    "{:.2e} l{:.1e}",
                    (st.energy.total() - e0) / (p.m * p.g * p.l),
                    s.lambda[0]
                ));
            }
        }
        println!("rho {rho} h {h}: {out:?} gdot {gd:e}");
    }
}

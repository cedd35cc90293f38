//! Shared fixtures of the results tests: a layout with every kind of column and deterministic
//! rows with full 52-bit mantissas (a lossy path would be caught by a bit comparison).
#![allow(dead_code)]

use flexmbs_io::results::{ResultsLayout, ResultsRow, SignalSpec};

/// xorshift64* numbers in [-1, 1).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn names(prefix: &str, n: usize) -> Vec<String> {
    (0..n).map(|i| format!("{prefix}{i}")).collect()
}

/// Layout with `nq` coordinates, `nu` velocities, `nc` multipliers and, when `signals`, a
/// 3-component `tip.position` in m and a 1-component `crank.angle` in rad.
pub fn layout(nq: usize, nu: usize, nc: usize, signals: bool) -> ResultsLayout {
    ResultsLayout {
        model: "slider crank µ".into(),
        coordinates: names("rod.q", nq),
        velocities: names("rod.u", nu),
        multipliers: names("pin.row", nc),
        signals: if signals {
            vec![
                SignalSpec {
                    name: "tip.position".into(),
                    unit: "m".into(),
                    components: vec!["x".into(), "y".into(), "z".into()],
                },
                SignalSpec {
                    name: "crank.angle".into(),
                    unit: "rad".into(),
                    components: vec!["phi".into()],
                },
            ]
        } else {
            Vec::new()
        },
    }
}

/// Owned data of one row.
#[derive(Debug, Clone)]
pub struct OwnedRow {
    pub t: f64,
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    pub lambda: Vec<f64>,
    pub energy: [f64; 4],
    pub drift: [f64; 2],
    pub step: [f64; 3],
    pub signals: Vec<f64>,
}

impl OwnedRow {
    pub fn view(&self) -> ResultsRow<'_> {
        ResultsRow {
            t: self.t,
            q: &self.q,
            u: &self.u,
            lambda: &self.lambda,
            energy: self.energy,
            drift: self.drift,
            step: self.step,
            signals: &self.signals,
        }
    }
}

/// `n` deterministic rows for `layout`, at t = 0.001 i.
pub fn rows(layout: &ResultsLayout, n: usize, seed: u64) -> Vec<OwnedRow> {
    let mut r = Rng::new(seed);
    let mut v = |k: usize| -> Vec<f64> { (0..k).map(|_| r.next()).collect() };
    (0..n)
        .map(|i| {
            let e = v(9);
            OwnedRow {
                t: 0.001 * i as f64,
                q: v(layout.coordinates.len()),
                u: v(layout.velocities.len()),
                lambda: v(layout.multipliers.len()),
                energy: [e[0], e[1], e[2], e[3]],
                drift: [e[4].abs(), e[5].abs()],
                step: [1e-3, (i % 4) as f64, e[8].abs() * 1e-10],
                signals: v(layout.signal_width()),
            }
        })
        .collect()
}

/// Bitwise equality of two rows (NaN-aware, distinguishes -0.0).
pub fn same_bits(a: &ResultsRow, b: &ResultsRow) -> bool {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    a.t.to_bits() == b.t.to_bits()
        && bits(a.q) == bits(b.q)
        && bits(a.u) == bits(b.u)
        && bits(a.lambda) == bits(b.lambda)
        && bits(&a.energy) == bits(&b.energy)
        && bits(&a.drift) == bits(&b.drift)
        && bits(&a.step) == bits(&b.step)
        && bits(a.signals) == bits(b.signals)
}

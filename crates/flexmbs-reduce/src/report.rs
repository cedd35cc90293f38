//! Frequency tables of modal analyses: text, CSV and JSON.

use crate::pipeline::PreparedBody;
use flexmbs_fe::reduction::ModalResult;
use serde::Serialize;

/// One row of a frequency table.
#[derive(Debug, Clone, Serialize)]
pub struct ModeRow {
    /// 1-based mode index.
    pub index: usize,
    /// Frequency in Hz (0 for rigid-body modes).
    pub frequency_hz: f64,
    /// Eigenvalue omega^2 in (rad/s)^2.
    pub omega2: f64,
    /// Dominant direction label.
    pub dominant: String,
    /// Effective modal mass fractions x, y, z.
    pub effective_mass_fraction: [f64; 3],
}

/// Rows of a modal result.
pub fn modal_rows(m: &ModalResult) -> Vec<ModeRow> {
    m.labels
        .iter()
        .zip(&m.omega2)
        .map(|(l, &w2)| ModeRow {
            index: l.index,
            frequency_hz: l.frequency_hz,
            omega2: w2,
            dominant: l.dominant.clone(),
            effective_mass_fraction: l.effective_mass_fraction,
        })
        .collect()
}

/// A fixed-width text table.
pub fn modal_table(rows: &[ModeRow]) -> String {
    let mut s = String::from(
        " mode   frequency [Hz]   dominant     eff. mass x   eff. mass y   eff. mass z\n",
    );
    for r in rows {
        s += &format!(
            "{:5}   {:14.6}   {:10}   {:11.4e}   {:11.4e}   {:11.4e}\n",
            r.index,
            r.frequency_hz,
            r.dominant,
            r.effective_mass_fraction[0],
            r.effective_mass_fraction[1],
            r.effective_mass_fraction[2]
        );
    }
    s
}

/// CSV with a header line.
pub fn modal_csv(rows: &[ModeRow]) -> String {
    let mut s =
        String::from("mode,frequency_hz,omega2,dominant,eff_mass_x,eff_mass_y,eff_mass_z\n");
    for r in rows {
        s += &format!(
            "{},{:.12e},{:.12e},{},{:.6e},{:.6e},{:.6e}\n",
            r.index,
            r.frequency_hz,
            r.omega2,
            r.dominant,
            r.effective_mass_fraction[0],
            r.effective_mass_fraction[1],
            r.effective_mass_fraction[2]
        );
    }
    s
}

/// The JSON document of `flexmbs modal --json`.
#[derive(Debug, Serialize)]
pub struct ModalJson {
    /// Body name.
    pub body: String,
    /// Nodes of the mesh.
    pub nodes: usize,
    /// Elements of the mesh.
    pub elements: usize,
    /// Independent DOFs.
    pub dofs: usize,
    /// Rigid-body modes found.
    pub rigid_modes: usize,
    /// Units of the model.
    pub units: String,
    /// The modes.
    pub modes: Vec<ModeRow>,
}

/// Builds the JSON document.
pub fn modal_json(name: &str, body: &PreparedBody, m: &ModalResult) -> ModalJson {
    ModalJson {
        body: name.to_string(),
        nodes: body.mesh.num_nodes(),
        elements: body.mesh.elements.len(),
        dofs: body.system.len(),
        rigid_modes: m.n_rigid,
        units: body.mesh.units.name().to_string(),
        modes: modal_rows(m),
    }
}

//! Writes a mesh as a CalculiX (Abaqus-format) deck, so the same mesh can be solved by `ccx`
//! (cross-checks and benchmarks).

use flexmbs_fe::mesh::Property;
use flexmbs_fe::{ElementKind, Mesh};
use std::fmt::Write;

/// The CalculiX element name of a kind.
pub fn ccx_element_name(kind: ElementKind) -> Option<&'static str> {
    Some(match kind {
        ElementKind::Hex8 => "C3D8",
        ElementKind::Hex8I => "C3D8I",
        ElementKind::Hex20 => "C3D20",
        ElementKind::Hex20R => "C3D20R",
        ElementKind::Tet10 => "C3D10",
        ElementKind::Beam2 => return None,
    })
}

/// Numbers are written with 13 significant digits: CalculiX rejects fields longer than 20 characters.
/// Deck text: `*NODE`, one `*ELEMENT` block per (kind, property), `*NSET`s, materials and
/// `*SOLID SECTION`s. Beam elements are not written (CalculiX expands beams into solids).
/// Returns an error message if the mesh has beams.
pub fn mesh_to_inp(mesh: &Mesh) -> Result<String, String> {
    let mut s = String::from("** written by flexmbs\n*NODE, NSET=NALL\n");
    for (i, x) in mesh.nodes.iter().enumerate() {
        let _ = writeln!(
            s,
            "{}, {:.12e}, {:.12e}, {:.12e}",
            mesh.node_ids[i], x[0], x[1], x[2]
        );
    }
    let mut groups: Vec<(ElementKind, usize)> = Vec::new();
    for e in &mesh.elements {
        if !groups.contains(&(e.kind, e.property)) {
            groups.push((e.kind, e.property));
        }
    }
    let mut eid = 1usize;
    for (g, &(kind, prop)) in groups.iter().enumerate() {
        let name =
            ccx_element_name(kind).ok_or("beam elements cannot be written to a CalculiX deck")?;
        let _ = writeln!(s, "*ELEMENT, TYPE={name}, ELSET=E{g}");
        for e in mesh
            .elements
            .iter()
            .filter(|e| e.kind == kind && e.property == prop)
        {
            let ids: Vec<String> = e
                .nodes
                .iter()
                .map(|&n| mesh.node_ids[n].to_string())
                .collect();
            // at most 16 entries per line: continuation after 15 node labels
            let mut line = eid.to_string();
            for (k, id) in ids.iter().enumerate() {
                if k == 15 {
                    let _ = writeln!(s, "{line},");
                    line = id.clone();
                } else {
                    line.push_str(", ");
                    line.push_str(id);
                }
            }
            let _ = writeln!(s, "{line}");
            eid += 1;
        }
    }
    for (name, set) in &mesh.node_sets {
        let _ = writeln!(s, "*NSET, NSET={}", name.to_uppercase());
        for chunk in set.chunks(16) {
            let ids: Vec<String> = chunk
                .iter()
                .map(|&n| mesh.node_ids[n].to_string())
                .collect();
            let _ = writeln!(s, "{},", ids.join(", "));
        }
    }
    for (g, &(_, prop)) in groups.iter().enumerate() {
        let Property::Solid { material } = &mesh.properties[prop] else {
            return Err("beam property on a solid element".into());
        };
        let _ = writeln!(
            s,
            "*MATERIAL, NAME=M{g}\n*ELASTIC\n{:.12e}, {:.12e}\n*DENSITY\n{:.12e}\n*SOLID SECTION, ELSET=E{g}, MATERIAL=M{g}",
            material.e, material.nu, material.rho
        );
    }
    Ok(s)
}

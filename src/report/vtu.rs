//! The deformed blank as an ASCII VTK UnstructuredGrid (`.vtu`, opens in ParaView).
//!
//! The file holds the FULL blank: when a quarter was solved, it is mirrored about x = 0 and
//! y = 0 (nodes on the symmetry planes shared, mirrored elements re-ordered to keep their
//! orientation). Cell data: `shear_deg` (signed; a single mirror image flips its sign, since it
//! swaps the acute and obtuse angles between the yarns), `t11_n`, `t22_n` and `tension_max_n`
//! (N per yarn). Point data: `contact` (0 free, 1 punch, 2 die, 3 die and holder) and
//! `displacement` (final − initial position, mm).

use std::fmt::Write as _;

use super::mirror::MirroredMesh;
use crate::core::drawing::DrawingResult;

/// VTK's cell type for a 4-node quadrilateral.
const VTK_QUAD: u8 = 9;

/// The full blank's mesh as indices into the solved part.
pub fn full_mesh(result: &DrawingResult) -> MirroredMesh {
    if result.quarter {
        MirroredMesh::of_quarter(&result.mesh.nodes, &result.mesh.quads)
    } else {
        MirroredMesh::identity(result.mesh.nodes.len(), &result.mesh.quads)
    }
}

/// The VTU text of a result.
pub fn vtu_string(result: &DrawingResult) -> String {
    let m = full_mesh(result);
    let np = m.nodes.len();
    let nc = m.quads.len();
    let mut s = String::with_capacity(64 * (np + nc) + 1024);
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    s.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">"
    );

    s.push_str("      <PointData Scalars=\"contact\" Vectors=\"displacement\">\n");
    open_array(&mut s, "UInt8", "contact", 1);
    for &(i, _) in &m.nodes {
        let _ = writeln!(s, "{}", result.contact.get(i).copied().unwrap_or(0));
    }
    close_array(&mut s);
    open_array(&mut s, "Float64", "displacement", 3);
    for n in 0..np {
        let x = m.point(n, &result.positions);
        let x0 = m.point(n, &result.mesh.nodes);
        let _ = writeln!(s, "{} {} {}", x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]);
    }
    close_array(&mut s);
    s.push_str("      </PointData>\n");

    s.push_str("      <CellData Scalars=\"shear_deg\">\n");
    let cell_field = |s: &mut String, name: &str, values: &[f64], signed: bool| {
        open_array(s, "Float64", name, 1);
        for &(e, [sx, sy]) in &m.elements {
            let sign = if signed { sx * sy } else { 1.0 };
            let _ = writeln!(s, "{}", sign * values[e]);
        }
        close_array(s);
    };
    cell_field(&mut s, "shear_deg", &result.shear_deg, true);
    cell_field(&mut s, "t11_n", &result.t11_n, false);
    cell_field(&mut s, "t22_n", &result.t22_n, false);
    cell_field(&mut s, "tension_max_n", &result.tension_max_n, false);
    s.push_str("      </CellData>\n");

    s.push_str("      <Points>\n");
    open_array(&mut s, "Float64", "points", 3);
    for n in 0..np {
        let x = m.point(n, &result.positions);
        let _ = writeln!(s, "{} {} {}", x[0], x[1], x[2]);
    }
    close_array(&mut s);
    s.push_str("      </Points>\n");

    s.push_str("      <Cells>\n");
    open_array(&mut s, "Int64", "connectivity", 1);
    for q in &m.quads {
        let _ = writeln!(s, "{} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    close_array(&mut s);
    open_array(&mut s, "Int64", "offsets", 1);
    for c in 0..nc {
        let _ = writeln!(s, "{}", 4 * (c + 1));
    }
    close_array(&mut s);
    open_array(&mut s, "UInt8", "types", 1);
    for _ in 0..nc {
        let _ = writeln!(s, "{VTK_QUAD}");
    }
    close_array(&mut s);
    s.push_str("      </Cells>\n");
    s.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    s
}

fn open_array(s: &mut String, ty: &str, name: &str, components: usize) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
    );
}

fn close_array(s: &mut String) {
    s.push_str("        </DataArray>\n");
}

//! One CSV table per rod: one row per vertex, units in the header.

use crate::number::push_number;
use crate::result::RodResult;

/// Header of a rod CSV: column names with their units (`_1pm` is 1/m).
pub const CSV_HEADER: &str = "s_m,x_m,y_m,z_m,fx_N,fy_N,fz_N,mx_Nm,my_Nm,mz_Nm,\
tangential_force_N,shear_force_N,bending_moment_Nm,torsion_Nm,\
Mx_Nm,My_Nm,Mz_Nm,hamiltonian_N,kappa1_1pm,kappa2_1pm,kappa3_1pm";

/// The CSV text of one rod: [`CSV_HEADER`] and one row per vertex (`N + 1` rows),
/// numbers in their shortest round-trip form (see [`push_number`]), `\n` line ends.
pub fn rod_csv(rod: &RodResult) -> String {
    let mut out = String::with_capacity(256 * (rod.s_m.len() + 1));
    out.push_str(CSV_HEADER);
    out.push('\n');
    for j in 0..rod.s_m.len() {
        let [x, y, z] = rod.position_m[j];
        let [fx, fy, fz] = rod.force_n[j];
        let [mx, my, mz] = rod.moment_nm[j];
        let [tx, ty, tz] = rod.total_moment_nm[j];
        let [k1, k2, k3] = rod.curvature_1pm[j];
        let row = [
            rod.s_m[j],
            x,
            y,
            z,
            fx,
            fy,
            fz,
            mx,
            my,
            mz,
            rod.tangential_force_n[j],
            rod.shear_force_n[j],
            rod.bending_moment_nm[j],
            rod.torsion_nm[j],
            tx,
            ty,
            tz,
            rod.hamiltonian_n[j],
            k1,
            k2,
            k3,
        ];
        for (k, value) in row.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            push_number(&mut out, *value);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_row_per_vertex_with_all_columns() {
        let rod = crate::tests::sample_rod();
        let text = rod_csv(&rod);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), rod.s_m.len() + 1);
        let columns = CSV_HEADER.split(',').count();
        assert_eq!(columns, 21);
        for line in &lines[1..] {
            assert_eq!(line.split(',').count(), columns);
            assert!(line.split(',').all(|v| v.parse::<f64>().is_ok()));
        }
        assert!(lines[2].starts_with("0.5,0.5,0,0,"), "{}", lines[2]);
        let values = [-7.163972553141504e-19, 2.5e20, 1e-5, -13.5];
        let mut s = String::new();
        for v in values {
            push_number(&mut s, v);
            s.push(' ');
        }
        assert_eq!(s, "-7.163972553141504e-19 2.5e20 0.00001 -13.5 ");
        let parsed: Vec<f64> = s.split_whitespace().map(|t| t.parse().unwrap()).collect();
        assert_eq!(parsed, values, "round trip");
    }
}

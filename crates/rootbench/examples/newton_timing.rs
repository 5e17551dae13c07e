// Scratch timing (not committed).
use signorini_contact::friction::{
    coulomb_fixed_point, coulomb_status, FrictionLaw, FrictionLayout, FrictionOptions, PointStatus,
};
use signorini_contact::DelassusProblem;
use signorini_rootbench::problem::Family;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let fam = if args[1] == "3" {
        Family::Coulomb3d
    } else {
        Family::Coulomb2d
    };
    let method = args[3].clone();
    for ms in args[2].split(',') {
        let m: usize = ms.parse().unwrap();
        let t0 = Instant::now();
        let p = fam.problem(m).unwrap();
        let (w, q) = p.in_blocks();
        let m = p.contacts();
        let d = p.dim;
        let build = t0.elapsed().as_secs_f64();
        let n = q.len();
        let qmax = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let dmax = (0..n).fold(0.0f64, |a, i| a.max(w[(i, i)].abs()));
        let layout = FrictionLayout {
            tangent_rows: (0..m)
                .map(|i| (0..d - 1).map(|k| m + (d - 1) * i + k).collect())
                .collect(),
            law: (0..m).map(|i| FrictionLaw::coulomb(p.mu[i])).collect(),
            shadow: vec![None; m],
        };
        let opts = FrictionOptions {
            max_iterations: 200,
            max_fixed_point: 200,
            tolerance: 1e-8,
            force_scale: qmax / dmax,
            gap_scale: qmax,
        };
        let mut problem = DelassusProblem::from_operator(w, q.clone());
        let initial: Vec<PointStatus> = (0..m)
            .map(|i| {
                if q[i] <= 0.0 {
                    PointStatus::Stick
                } else {
                    PointStatus::Open
                }
            })
            .collect();
        let t = Instant::now();
        let out = match (d, method.as_str()) {
            (3, _) => {
                let t = Instant::now();
                let r =
                    signorini_contact::friction3d::friction_3d(&mut problem, &layout, None, &opts);
                eprintln!("solve {:.3}", t.elapsed().as_secs_f64());
                r
            }
            (_, "status") => coulomb_status(&mut problem, &layout, initial, &opts),
            (_, "fp") => coulomb_fixed_point(&mut problem, &layout, initial, None, &opts),
            _ => signorini_contact::friction::coulomb_newton(&mut problem, &layout, None, &opts),
        }
        .unwrap();
        let el = t.elapsed().as_secs_f64();
        let act = out
            .statuses
            .iter()
            .filter(|s| **s != PointStatus::Open)
            .count();
        let slip = out.statuses.iter().filter(|s| s.is_slip()).count();
        let sumn: f64 = out.forces[..m].iter().sum();
        println!(
            "{} m={m} method={method} time={el:.3}s (build {build:.1}s) conv={} it={} fp={} active={act} slip={slip} sum_n={sumn:.10e} reason={}",
            p.name, out.converged, out.iterations, out.fixed_point_iterations, out.stopping_reason
        );
    }
}

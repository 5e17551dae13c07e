use signorini_rootbench::problem::Family;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let m: usize = a[2].parse().unwrap();
    let fam = Family::ALL.iter().find(|f| f.name() == a[1]).unwrap();
    let p = fam.problem(m).unwrap();
    signorini_solver::problem_file::write_npz(
        std::path::Path::new(&format!("/tmp/{}.npz", p.name)),
        &p.w,
        &p.q,
        &p.mu,
        p.dim,
    )
    .unwrap();
    println!("/tmp/{}.npz", p.name);
}

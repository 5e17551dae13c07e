//! The interface of many subdomains (course notes §8.3): S = Σ S_i
//! never assembled, factorised over a tree of the subdomains (their dense
//! blocks merged two by two, the glue eliminated at each merge), floating
//! bodies by fixing DOFs instead of S + ρRRᵀ. Each run must equal the
//! unsplit body (dense S) and the direct path.

use crate::common;

use common::{assert_same, converged_on as solve, example, with_subdomains};
use signorini_report::InterfaceFactorisation;
use signorini_scene::SolvePath;
use signorini_solver::RunOutput;

fn interface(o: &RunOutput) -> &InterfaceFactorisation {
    o.report
        .factorisation
        .as_ref()
        .and_then(|f| f.interface.as_ref())
        .expect("the condensed path reports its interface factorisation")
}

fn hertz3d(divisions: usize) -> String {
    example("hertz3d.toml").replace("divisions = 12,", &format!("divisions = {divisions},"))
}

#[test]
fn sphere_in_8_and_32_parts_equals_the_unsplit_sphere_with_a_tree_factor() {
    let one = hertz3d(8);
    let a = solve(&one, SolvePath::Condensed);
    assert_eq!(interface(&a).storage, "dense", "one subdomain: one dense S");
    let direct = solve(&one, SolvePath::Direct);
    assert_same(&a, &direct, 1e-8);
    for parts in [8, 32] {
        let split = with_subdomains(&one, "material = \"steel\"\n", parts);
        let b = solve(&split, SolvePath::Condensed);
        assert_eq!(b.report.subdomains, parts);
        let i = interface(&b);
        assert_eq!(i.storage, "tree", "{parts} parts: {i:?}");
        let n = i.rows;
        assert!(i.factor_bytes < 8 * n * n / 2, "{parts} parts: {i:?}");
        assert_eq!(i.ordering.as_deref(), Some("subdomain_tree"));
        let flops = i.sparse_flops.expect("the tree's flops");
        assert!(
            flops > 0.0 && flops < (n as f64).powi(3) / 6.0,
            "{parts} parts: {i:?}"
        );
        assert_eq!(i.fixing_dofs, 0, "the sphere is held");
        assert_same(&a, &b, 1e-8);
    }
}

#[test]
fn floating_box_in_parts_uses_fixing_dofs_and_equals_the_unsplit_box() {
    let one = common::example_with(
        "floating3d.toml",
        &[
            ("divisions = [5, 4, 2]", "divisions = [12, 10, 4]"),
            ("method = \"mprgp\"", "method = \"status\""),
        ],
    );
    let a = solve(&one, SolvePath::Condensed);
    let split = with_subdomains(&one, "material = \"aluminium\"\n", 6);
    let b = solve(&split, SolvePath::Condensed);
    let i = interface(&b);
    assert_eq!(i.storage, "tree", "{i:?}");
    // pin (x, y) and roller (y) leave z and the rotations about x and y free.
    assert_eq!(i.fixing_dofs, 3, "{i:?}");
    assert_same(&a, &b, 1e-8);
    let c = solve(&split, SolvePath::Direct);
    assert_same(&b, &c, 1e-8);
}

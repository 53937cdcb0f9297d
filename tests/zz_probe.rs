//! probe
#![allow(missing_docs)]
use prbfit::mech::exact;
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};
use prbfit::beam::{Effects, Resolution, BeamSolver, BeamModel, Load};
use Coordinate::Loaded;
#[test]
fn probe() {
    let f = |root: [f64;2]| Flexure { root, angle: 0.0, attach: Attach::Clamped, beam: BeamSpec { length: 1.0, width: 1.0, thickness: 0.01, youngs_modulus: 12e6, poisson_ratio: 0.3, shear_coefficient: None, effects: EffectsChoice::Fixed(Effects::NONE) } };
    let m = Mechanism { flexures: vec![f([0.0,0.3]), f([0.0,-0.3])], stage_point: [1.0,0.0], drives: vec![Drive{coordinates:[Loaded(-0.9409964357094339), Loaded(1.878026452355475), Loaded(0.2990512725617043)], steps:2}]};
    let c = exact::solve(&m, Resolution::with_tol(1e-10)).unwrap();
    let s = BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-10)).unwrap();
    for c in &c[0] { for f in &c.flexures { println!("{:?}", f); let sol = s.solve(f.wrench).unwrap(); println!("  loaded: {:?} stab {:?}", sol.tip, sol.convergence); let r = s.shoot_root(f.wrench.alpha_x, f.wrench.alpha_y, 0.0); let _ = r; } }
    let _ = Load::default();
}

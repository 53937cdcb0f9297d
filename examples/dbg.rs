use prbfit::beam::*;
fn main() {
    let s = BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-12)).unwrap();
    let x = s.solve(Load::new(-3.0, 0.01, 0.0)).unwrap();
    println!("{:?} it {} cs {} rk {}", x.tip, x.iterations, x.continuation_steps, x.rk_steps);
}

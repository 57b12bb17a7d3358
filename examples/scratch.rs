use linkdyn::formulation::{Dae, DaeOptions, Formulation};
fn main() {
    for f in [
        "models/fourbar_ideal.toml",
        "models/pendulum.toml",
        "models/double_pendulum.toml",
        "models/slider_crank.toml",
    ] {
        let model = linkdyn::model::load(f.as_ref(), &[]).unwrap();
        let dae = Dae::new(&model, &DaeOptions::default()).unwrap();
        let a = dae.assembly();
        println!(
            "{f}: dof {} rank {} red {:?} it {} res {:e}",
            a.dof, a.rank, a.redundant_rows, a.iterations, a.residual
        );
        println!(" q {:?}\n v {:?}", a.q, a.v);
        let y = dae.initial_state();
        let mut dy = vec![0.0; y.len()];
        dae.rhs(0.0, &y, &mut dy).unwrap();
        println!(" acc {:?}", &dy[y.len() / 2..]);
        let t0 = std::time::Instant::now();
        for _ in 0..1000000 {
            dae.rhs(0.0, &y, &mut dy).unwrap();
        }
        println!(" rhs {:?}", t0.elapsed() / 1000000);
    }
}

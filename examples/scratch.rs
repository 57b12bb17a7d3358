use linkdyn::formulation::{Dae, DaeOptions, Formulation};
fn main() {
    let model = linkdyn::model::load("models/farahan2016.toml".as_ref(), &[]).unwrap();
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap();
    let mut y = dae.initial_state();
    y[5] += 0.003; // rotate coupler a bit -> moves bearing
    let mut dy = vec![0.0; y.len()];
    dae.rhs(0.0, &y, &mut dy).unwrap();
    let s = dae.contact_state(0, &y);
    println!(
        "delta {:e} fn {:e} on_journal {:?}",
        s.kinematics.delta, s.forces.normal_force, s.forces.on_journal
    );
    println!("acc {:?}", &dy[9..18]);
}

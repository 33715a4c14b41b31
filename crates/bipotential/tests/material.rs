//! Materials of a layered, wet ground: an elastic point never flows, and a pore pressure
//! moves the Drucker-Prager cone along the hydrostatic axis, so that yield acts on the
//! effective stress `σ' = σ + p_w I` (Terzaghi's principle, tension positive).
use talus_bipotential::{
    ConeFit, DruckerPrager, DruckerPragerParameters, Elastic, Material, Projector, SVector,
};

fn soil(friction_angle: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 2e7,
        poisson_ratio: 0.3,
        friction_angle,
        cohesion: 5e3,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap()
}

#[test]
fn an_elastic_point_has_residual_rho_z_and_identity_blocks() {
    let rule = Material::Elastic(Elastic::try_new(3e7, 0.25).unwrap()).flow_rule::<4>(1e4);
    let sigma = SVector::<f64, 4>::new(-3e5, 2e5, -1e4, 7e4);
    let z = SVector::<f64, 4>::new(1e-3, -2e-3, 5e-4, 3e-3);
    let rho = 7.5e6;
    let lin = rule.natural_map_linearization(&sigma, &z, rho);
    // σ − P(σ − ρ z) with P the identity: ρ z, whatever σ (even far outside any cone).
    assert!((lin.residual - z * rho).norm() <= 1e-12 * (z * rho).norm());
    assert_eq!(
        lin.projection_jacobian,
        nalgebra::SMatrix::<f64, 4, 4>::identity()
    );
    assert_eq!(lin.coupling, nalgebra::SMatrix::<f64, 4, 4>::identity());
    assert_eq!(lin.region, talus_bipotential::Region::Interior);
}

#[test]
fn elastic_parameters_out_of_range_are_named() {
    for (e, nu, name) in [(0.0, 0.3, "young_modulus"), (1e7, 0.5, "poisson_ratio")] {
        let err = Elastic::try_new(e, nu).unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
    }
}

#[test]
fn without_pore_pressure_the_rule_is_the_materials_bit_for_bit() {
    let m = soil(30.0);
    assert_eq!(
        Material::DruckerPrager(m).flow_rule::<4>(0.0),
        m.flow_rule::<4>()
    );
}

/// A total stress `σ = σ' − p_w I` is projected onto the moved cone exactly where its
/// effective stress `σ'` is projected onto the dry cone, shifted back: `P_{K − pI}(σ) =
/// P_K(σ + pI) − pI`, for points in each of the three regions (inside, onto the surface,
/// onto the apex).
#[test]
fn the_moved_cone_projects_total_stress_as_the_dry_one_projects_effective_stress() {
    let m = soil(30.0);
    let p_w = 4.2e4;
    let shift = SVector::<f64, 4>::new(p_w, p_w, p_w, 0.0);
    let dry = m.flow_rule::<4>();
    let wet = Material::DruckerPrager(m).flow_rule::<4>(p_w);
    let effective = [
        SVector::<f64, 4>::new(-1e5, -1.2e5, -1e5, 1e3), // inside
        SVector::<f64, 4>::new(-1e5, -3e5, -1e5, 9e4),   // onto the surface
        SVector::<f64, 4>::new(2e5, 1.5e5, 1.8e5, 1e3),  // onto the apex
    ];
    let mut regions = Vec::new();
    for s_eff in effective {
        let total = s_eff - shift;
        let pd = dry.yield_set().project(&s_eff);
        let pw = wet.yield_set().project(&total);
        regions.push(pd.region);
        assert_eq!(pd.region, pw.region);
        let expected = pd.point - shift;
        assert!(
            (pw.point - expected).norm() <= 1e-10 * expected.norm(),
            "{:?} vs {:?}",
            pw.point,
            expected
        );
    }
    regions.dedup();
    assert_eq!(
        regions.len(),
        3,
        "the three regions are visited: {regions:?}"
    );
    // The yield function of the effective stress is zero on the moved cone's surface.
    let on_surface = wet.yield_set().project(&(effective[1] - shift)).point + shift;
    assert!(m.yield_function(&on_surface).abs() <= 1e-9 * on_surface.norm());
}

#[test]
fn a_von_mises_cylinder_does_not_move_under_pore_pressure() {
    let m = soil(0.0);
    assert_eq!(
        Material::DruckerPrager(m).flow_rule::<4>(1e5),
        m.flow_rule::<4>()
    );
}

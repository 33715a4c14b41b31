//! The pictures' scales and labels (issue 27, item 4), tested on the functions that decide
//! them, not on pixels: the colour scale of a map (clipped at a percentile, uniform) and
//! the force axis's unit.
use talus::output::{force_axis_label, ColourScale};
use talus::scene::GeometryKind;

/// 0, 0.001, …, 0.999 and one spike of 50 at the end (a footing's corner).
fn ramp_with_spike() -> Vec<f64> {
    let mut v: Vec<f64> = (0..1000).map(|i| i as f64 / 1000.0).collect();
    v.push(50.0);
    v
}

#[test]
fn a_spike_is_clipped_at_the_percentile_not_the_max() {
    let v = ramp_with_spike();
    let s = ColourScale::clipped(&v, 99.0);
    // 1001 values: rank 0.99 × 1000 = 990, the value 0.990.
    assert!((s.hi - 0.990).abs() < 1e-12, "top of the colours {}", s.hi);
    assert_eq!(s.clipped_at, Some(99.0));
    assert_eq!((s.lo, s.min, s.max), (0.0, 0.0, 50.0));
    // The spike is drawn in the top colour, the ramp's 0.5 halfway up.
    assert_eq!(s.t(50.0), 1.0);
    assert!((s.t(0.495) - 0.5).abs() < 1e-12);
    // The picture says so, with the maximum, and the top label is "≥ …", not "(max)".
    let note = s.note().expect("a clipped scale has a note");
    assert!(note.contains("99th percentile"), "{note}");
    assert!(note.contains("max = 50"), "{note}");
    let ticks = s.ticks();
    let top = &ticks.last().unwrap().1;
    assert_eq!(top, "≥ 0.99");
    assert!(ticks.iter().all(|(_, t)| !t.contains("(max)")), "{ticks:?}");
}

#[test]
fn a_smooth_field_or_a_lone_peak_on_a_uniform_field_is_not_clipped() {
    // The top 1 % of a ramp stretches its scale by 1 %: not worth a clip.
    let ramp: Vec<f64> = (0..1000).map(|i| i as f64).collect();
    let s = ColourScale::clipped(&ramp, 99.0);
    assert_eq!((s.hi, s.clipped_at), (999.0, None));
    assert!(s.note().is_none());
    assert_eq!(s.ticks().last().unwrap().1, "999 (max)");
    // Zero everywhere but one element: clipping would hide the peak.
    let mut peak = vec![0.0; 500];
    peak[7] = 1.0;
    let s = ColourScale::clipped(&peak, 99.0);
    assert_eq!((s.hi, s.clipped_at), (1.0, None));
    assert_eq!(s.t(1.0), 1.0);
}

#[test]
fn a_uniform_field_has_one_colour_and_one_label() {
    // Constant to round-off: every element the same colour, one label with the value.
    let v = [2.5e3, 2.5e3 * (1.0 + 1e-13), 2.5e3 * (1.0 - 2e-13), 2.5e3];
    for s in [ColourScale::full(&v), ColourScale::clipped(&v, 99.0)] {
        assert!(s.is_uniform(), "{s:?}");
        let t: Vec<f64> = v.iter().map(|&x| s.t(x)).collect();
        assert!(t.iter().all(|&x| x == t[0]), "colours {t:?}");
        let ticks = s.ticks();
        assert_eq!(ticks.len(), 1, "{ticks:?}");
        assert!((ticks[0].0 - 2.5e3).abs() < 1e-6);
        assert_eq!(ticks[0].1, "2500 (uniform)");
        assert!(s.note().is_none());
    }
    // All zero.
    let s = ColourScale::full(&[0.0; 4]);
    assert!(s.is_uniform());
    assert_eq!(s.ticks(), vec![(0.0, "0 (uniform)".to_string())]);
}

#[test]
fn a_small_but_real_variation_keeps_its_scale_and_distinct_labels() {
    // 1 to 1.0004: not uniform (4e-4 of the magnitude), and no two labels read the same.
    let v = [1.0, 1.0001, 1.0004];
    let s = ColourScale::full(&v);
    assert!(!s.is_uniform());
    assert_eq!((s.t(1.0), s.t(1.0004)), (0.0, 1.0));
    let ticks = s.ticks();
    let mut texts: Vec<&str> = ticks
        .iter()
        .map(|(_, t)| t.trim_end_matches(" (min)").trim_end_matches(" (max)"))
        .collect();
    assert!(ticks.len() >= 3, "{ticks:?}");
    texts.sort_unstable();
    texts.dedup();
    assert_eq!(texts.len(), ticks.len(), "labels repeat: {ticks:?}");
}

#[test]
fn the_force_axis_is_in_kn_axisymmetric_and_kn_per_m_in_plane_strain() {
    assert_eq!(
        force_axis_label(GeometryKind::Axisymmetric.force_unit()),
        "Force F [kN]"
    );
    assert_eq!(
        force_axis_label(GeometryKind::PlaneStrain.force_unit()),
        "Force F [kN/m]"
    );
}

#[test]
fn a_force_unit_that_is_not_newtons_is_refused() {
    let dir = std::env::temp_dir().join(format!("talus-pictures-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let err = talus::output::plot_force_displacement_with_unit(
        &dir.join("f.png"),
        &[(0.0, 0.0), (1e-3, 1e3)],
        "t",
        "kN",
    )
    .unwrap_err();
    assert!(err.to_string().contains("force_unit"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

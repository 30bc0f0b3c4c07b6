use super::*;
use crate::measured::Tabulated;

/// A small deterministic generator (SplitMix64) so the tests do not depend on a crate.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.next().max(1e-300), self.next());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    fn hemisphere(&mut self) -> Vec3 {
        // Uniform in solid angle over the upper hemisphere, kept off grazing (θ < 80°).
        let z = 0.18 + 0.82 * self.next();
        let phi = std::f64::consts::TAU * self.next();
        let s = (1.0 - z * z).sqrt();
        Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32)
    }
}

/// Half the views near the mirror direction, as a gonioreflectometer scan around the peak would take them.
fn samples(model: &Model, count: usize, noise: f64, seed: u64) -> Vec<Sample> {
    let mut rng = Rng(seed);
    (0..count)
        .map(|i| {
            let l = rng.hemisphere();
            let v = if i % 2 == 0 {
                let r = Vec3::new(-l.x, -l.y, l.z);
                (r + 0.3 * rng.hemisphere()).normalize()
            } else {
                rng.hemisphere()
            };
            let g = Geometry::new(l, v, Vec3::Z, None).unwrap();
            let f = model.eval(&g) * Vec3::from_array([0, 1, 2].map(|_| (noise * rng.normal()).exp() as f32));
            Sample { l, v, n: Vec3::Z, f }
        })
        .collect()
}

fn num(x: f64) -> Input {
    Input::Number(x)
}

fn ct(roughness: f64, kd: [f64; 3], f0: [f64; 3]) -> Model {
    Model::build(
        "cook_torrance",
        &[
            ("roughness".into(), num(roughness)),
            ("kd".into(), Input::Numbers(kd.to_vec())),
            ("f0".into(), Input::Numbers(f0.to_vec())),
        ],
    )
    .unwrap()
}

fn value<'a>(r: &'a FitReport, name: &str) -> &'a [f64] {
    &r.values.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("{name} not fitted: {r:?}")).1
}

#[test]
fn cook_torrance_is_recovered_with_no_start_and_every_parameter_free() {
    let truth = ct(0.22, [0.5, 0.3, 0.1], [0.04, 0.05, 0.06]);
    let data = samples(&truth, 3000, 0.0, 1);
    let res = fit_model("cook_torrance", &data, &FitOptions::default()).unwrap();
    eprintln!(
        "{:?}\n{:?} {:?} {} it {}",
        res.values, res.at_bound, res.inactive, res.iterations, res.message
    );
    assert!(res.converged, "{}", res.message);
    assert!((value(&res, "roughness")[0] - 0.22).abs() < 1e-3, "{:?}", res.values);
    for (got, want) in value(&res, "kd").iter().zip([0.5, 0.3, 0.1]) {
        assert!((got - want).abs() < 1e-3, "{:?}", res.values);
    }
    for (got, want) in value(&res, "f0").iter().zip([0.04, 0.05, 0.06]) {
        assert!((got - want).abs() < 1e-3, "{:?}", res.values);
    }
    assert!(value(&res, "ks").iter().all(|x| (x - 1.0).abs() < 1e-3), "{:?}", res.values);
    // Schlick's Fresnel: the other Fresnel inputs and the absent second lobe change nothing.
    for p in ["ior", "eta", "k", "roughness2", "weight2"] {
        assert!(res.inactive.iter().any(|n| n == p), "{p} {:?}", res.inactive);
    }
    assert!(res.channels.iter().all(|c| c.relative_l2 < 1e-3), "{:?}", res.channels);
}

#[test]
fn fixed_parameters_stay_fixed_and_every_loss_recovers_the_rest() {
    let truth = ct(0.3, [0.2, 0.4, 0.6], [0.04; 3]);
    let data = samples(&truth, 1500, 0.0, 2);
    for loss in [Loss::Log, Loss::CubeRoot, Loss::CosineRelative, Loss::Linear] {
        let o = FitOptions {
            fixed: vec![("f0".into(), num(0.04)), ("ks".into(), num(1.0))],
            loss,
            ..FitOptions::default()
        };
        let res = fit_model("cook_torrance", &data, &o).unwrap();
        assert!(res.values.iter().all(|(n, _)| n != "f0" && n != "ks"), "{:?}", res.values);
        assert_eq!(res.model, ct_with(&res, 0.04));
        assert!((value(&res, "roughness")[0] - 0.3).abs() < 1e-3, "{loss:?} {:?}", res.values);
        for (got, want) in value(&res, "kd").iter().zip([0.2, 0.4, 0.6]) {
            assert!((got - want).abs() < 1e-3, "{loss:?} {:?}", res.values);
        }
    }
}

fn ct_with(res: &FitReport, f0: f64) -> Model {
    let kd = value(res, "kd").to_vec();
    Model::build(
        "cook_torrance",
        &[
            ("f0".into(), num(f0)),
            ("ks".into(), num(1.0)),
            ("kd".into(), Input::Numbers(kd)),
            ("roughness".into(), num(value(res, "roughness")[0])),
        ],
    )
    .unwrap()
}

#[test]
fn lambert_to_lambert_data_is_exact_and_albedo_above_one_ends_on_the_bound() {
    let truth = Model::build("lambert", &[("kd".into(), Input::Numbers(vec![0.7, 0.2, 0.05]))]).unwrap();
    let res = fit_model("lambert", &samples(&truth, 200, 0.0, 3), &FitOptions::default()).unwrap();
    for (got, want) in value(&res, "kd").iter().zip([0.7, 0.2, 0.05]) {
        assert!((got - want).abs() < 1e-6, "{:?}", res.values);
    }
    assert!(res.cost < 1e-20, "{}", res.cost);
    let bright: Vec<Sample> = (0..50)
        .map(|i| {
            let l = Vec3::new(0.1 * (i as f32 * 0.3).sin(), 0.2, 1.0);
            Sample { l, v: Vec3::new(-0.3, 0.1, 1.0), n: Vec3::Z, f: Vec3::splat(0.6) }
        })
        .collect();
    let res = fit_model("lambert", &bright, &FitOptions::default()).unwrap();
    assert!(value(&res, "kd").iter().all(|&a| a > 1.0 - 1e-6 && a <= 1.0), "{:?}", res.values);
    assert_eq!(res.at_bound.len(), 3, "{:?}", res.at_bound);
    assert!(res.stderr[0].1.iter().all(|s| s.is_nan()));
}

#[test]
fn standard_errors_shrink_as_one_over_root_n_and_match_the_spread_of_noisy_fits() {
    let truth = ct(0.25, [0.4; 3], [0.04; 3]);
    let o =
        FitOptions { fixed: vec![("ks".into(), num(1.0)), ("f0".into(), num(0.04))], ..Default::default() };
    let mut fitted = Vec::new();
    let mut se = Vec::new();
    for seed in 0..8 {
        let r = fit_model("cook_torrance", &samples(&truth, 800, 0.05, 100 + seed), &o).unwrap();
        fitted.push(value(&r, "roughness")[0]);
        se.push(r.stderr_robust.iter().find(|(n, _)| n == "roughness").unwrap().1[0]);
    }
    let mean = fitted.iter().sum::<f64>() / 8.0;
    let spread = (fitted.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 7.0).sqrt();
    let se_mean = se.iter().sum::<f64>() / 8.0;
    eprintln!("roughness spread {spread:.2e}, mean standard error {se_mean:.2e}");
    assert!(spread / se_mean > 0.4 && spread / se_mean < 2.5, "{spread} {se_mean}");
    let big = fit_model("cook_torrance", &samples(&truth, 3200, 0.05, 200), &o).unwrap();
    let se_big = big.stderr_robust.iter().find(|(n, _)| n == "roughness").unwrap().1[0];
    // Four times the samples: half the standard error.
    assert!((se_mean / se_big - 2.0).abs() < 0.5, "{se_mean} {se_big}");
}

#[test]
fn a_choice_search_finds_the_distribution_of_the_data() {
    let truth = Model::build(
        "cook_torrance",
        &[("distribution".into(), Input::Text("beckmann".into())), ("roughness".into(), num(0.2))],
    )
    .unwrap();
    let data = samples(&truth, 1500, 0.0, 4);
    let o = FitOptions {
        choices: vec![("distribution".into(), vec!["ggx".into(), "beckmann".into()])],
        ..Default::default()
    };
    let res = fit_model("cook_torrance", &data, &o).unwrap();
    assert_eq!(res.choices, vec![("distribution".to_string(), "beckmann".to_string())]);
    assert_eq!(res.tried.len(), 2);
    assert!((value(&res, "roughness")[0] - 0.2).abs() < 1e-3, "{:?}", res.values);
}

#[test]
fn a_table_made_from_a_model_gives_samples_that_recover_it() {
    let truth = ct(0.3, [0.3, 0.2, 0.1], [0.04; 3]);
    let table = Tabulated::from_model(&truth, (90, 90, 180)).unwrap();
    for strategy in [Strategy::Cosine, Strategy::HalfDiff] {
        let how = TableSampling { count: 5000, strategy, ..Default::default() };
        let s = table_samples(&table, &how).unwrap();
        assert_eq!(s.len(), 5000);
        let cut = 80f32.to_radians().cos();
        assert!(s.iter().all(|x| x.l.z > cut && x.v.z > cut));
        let res = fit_model("cook_torrance", &s, &FitOptions::default()).unwrap();
        eprintln!("{strategy:?}: {:?}", res.values);
        // The table interpolates: the fit recovers the model to the table's accuracy.
        assert!((value(&res, "roughness")[0] - 0.3).abs() < 0.01, "{:?}", res.values);
        for (got, want) in value(&res, "kd").iter().zip([0.3, 0.2, 0.1]) {
            assert!((got - want).abs() < 0.01, "{:?}", res.values);
        }
    }
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let truth = ct(0.2, [0.5, 0.3, 0.1], [0.04; 3]);
    // Enough samples for the batch evaluator's parallel path.
    let data = samples(&truth, 20_000, 0.02, 5);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| {
            let o = FitOptions { fixed: vec![("ks".into(), num(1.0))], multistart: 2, ..Default::default() };
            fit_model("cook_torrance", &data, &o).unwrap()
        })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a, b);
}

#[test]
fn bad_requests_are_refused_naming_the_argument() {
    let s = samples(&Model::build("lambert", &[]).unwrap(), 10, 0.0, 6);
    let o = FitOptions::default();
    let e = fit_model("nope", &s, &o).unwrap_err().to_string();
    assert!(e.contains("nope") && e.contains("lambert"), "{e}");
    let with = |f: &dyn Fn(&mut FitOptions)| {
        let mut o = FitOptions::default();
        f(&mut o);
        fit_model("cook_torrance", &s, &o).unwrap_err().to_string()
    };
    let e = with(&|o| o.fixed = vec![("roughnes".into(), num(0.1))]);
    assert!(e.starts_with("fixed:") && e.contains("roughnes"), "{e}");
    let e = with(&|o| o.start = vec![("albedo".into(), num(0.1))]);
    assert!(e.starts_with("start:") && e.contains("kd"), "{e}");
    let e = with(&|o| o.start = vec![("roughness".into(), num(3.0))]);
    assert!(e.starts_with("start:") && e.contains("[0, 2]"), "{e}");
    let e = with(&|o| o.start = vec![("masking".into(), Input::Text("smith".into()))]);
    assert!(e.contains("scalar and color"), "{e}");
    let e = with(&|o| {
        o.fixed = vec![("kd".into(), num(0.5))];
        o.start = vec![("kd".into(), num(0.5))];
    });
    assert!(e.contains("both fixed and free"), "{e}");
    let e = with(&|o| o.choices = vec![("distribution".into(), vec!["ggz".into()])]);
    assert!(e.starts_with("choices:") && e.contains("ggz"), "{e}");
    let e = with(&|o| o.choices = vec![("roughness".into(), vec!["ggx".into()])]);
    assert!(e.starts_with("choices:") && e.contains("not a discrete choice"), "{e}");
    let e = with(&|o| o.weights = Some(vec![1.0; 3]));
    assert!(e.starts_with("weights:") && e.contains("10"), "{e}");
    let e = with(&|o| o.weights = Some(vec![-1.0; 10]));
    assert!(e.starts_with("weights:"), "{e}");
    assert!(Loss::from_name("l2").unwrap_err().to_string().contains("cube_root"));
    let below = [Sample { l: -Vec3::Z, v: Vec3::Z, n: Vec3::Z, f: Vec3::ONE }];
    let e = fit_model("lambert", &below, &o).unwrap_err().to_string();
    assert!(e.contains("above the surface"), "{e}");
    let mut nan = s.clone();
    nan[4].f.y = f32::NAN;
    let e = fit_model("lambert", &nan, &o).unwrap_err().to_string();
    assert!(e.contains("values") && e.contains("row 4"), "{e}");
    let zero: Vec<Sample> = s.iter().map(|x| Sample { f: Vec3::ZERO, ..*x }).collect();
    let e = fit_model("lambert", &zero, &o).unwrap_err().to_string();
    assert!(e.contains("values") && e.contains("0"), "{e}");
    let e = fit_model("cook_torrance", &s[..1], &o).unwrap_err().to_string();
    assert!(e.starts_with("samples:") && e.contains("fewer"), "{e}");
    let all = FitOptions { fixed: vec![("kd".into(), num(0.5))], ..Default::default() };
    let e = fit_model("lambert", &s, &all).unwrap_err().to_string();
    assert!(e.contains("nothing to fit"), "{e}");
}

#[test]
fn analytic_jacobians_match_central_differences() {
    let truth = ct(0.2, [0.5, 0.3, 0.1], [0.04, 0.05, 0.06]);
    let data = prepare(&samples(&truth, 400, 0.0, 7), None, None).unwrap();
    let cases: [(&str, Vec<Free>, Vec<f64>); 2] = [
        ("lambert", vec![free("kd", true, 0.0, 1.0)], vec![0.3, 0.6, 0.2]),
        (
            "cook_torrance",
            vec![
                free("kd", true, 0.0, 1.0),
                free("ks", true, 0.0, 1.0),
                free("roughness", false, 0.0, 2.0),
                free("f0", true, 0.0, 1.0),
            ],
            vec![0.4, 0.2, 0.1, 0.8, 0.7, 0.9, 0.3, 0.05, 0.1, 0.5],
        ),
    ];
    for (name, free, p) in cases {
        for loss in [Loss::Log, Loss::CubeRoot, Loss::CosineRelative, Loss::Linear] {
            let mut pr = Problem {
                name,
                base: vec![],
                free: free.clone(),
                data: data.clone(),
                loss,
                eps: 1e-3,
                analytic: None,
            };
            let model = Model::build(name, &pr.inputs(&p)).unwrap();
            pr.analytic = analytic::Analytic::for_problem(&model, &pr.free);
            assert!(pr.analytic.is_some(), "{name}");
            let exact = pr.jacobian(&p);
            let fd = lm::jacobian(&|q: &[f64]| pr.residuals(q), &p, &pr.bounds(), 3 * data.len());
            for (j, (a, b)) in exact.iter().zip(&fd).enumerate() {
                let scale = a.iter().map(|x| x.abs()).fold(0.0, f64::max);
                let err = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
                // Central differences of float32 model values: ~1e-3 of the column's scale.
                assert!(err <= 3e-3 * scale, "{name} {loss:?} column {j}: {err:.3e} of {scale:.3e}");
            }
        }
    }
    // Not written for Beckmann: the fit falls back to differences.
    let beck =
        Model::build("cook_torrance", &[("distribution".into(), Input::Text("beckmann".into()))]).unwrap();
    assert!(analytic::Analytic::for_problem(&beck, &[free("roughness", false, 0.0, 2.0)]).is_none());
}

fn free(name: &'static str, color: bool, lo: f64, hi: f64) -> Free {
    Free { name, color, lo, hi, started: false }
}

#[test]
fn analytic_and_finite_difference_fits_agree() {
    let truth = ct(0.15, [0.3, 0.2, 0.6], [0.05; 3]);
    let data = samples(&truth, 2000, 0.03, 8);
    let a = fit_model("cook_torrance", &data, &FitOptions::default()).unwrap();
    let fd = FitOptions { jacobian: Jacobian::FiniteDifference, ..Default::default() };
    let b = fit_model("cook_torrance", &data, &fd).unwrap();
    assert_eq!((a.jacobian, b.jacobian), ("analytic", "finite_difference"));
    // Both reach the same minimum: their gap is tiny against the statistical uncertainty of the fit
    // (values on a bound, whose stderr is NaN, are on the same bound).
    for (((n, x), (_, y)), (_, s)) in a.values.iter().zip(&b.values).zip(&a.stderr) {
        for ((x, y), s) in x.iter().zip(y).zip(s) {
            if s.is_nan() {
                assert_eq!(x, y, "{n} on a bound");
            } else {
                assert!((x - y).abs() < 0.05 * s, "{n}: {x} {y}, stderr {s}");
            }
        }
    }
    assert!((a.cost - b.cost).abs() <= 1e-5 * a.cost, "cost {} vs {}", a.cost, b.cost);
}

#[test]
fn an_anisotropic_table_fits_to_the_parameters_of_its_model_with_no_start() {
    use crate::measured::AnisotropicTabulated;
    let truth = Model::build(
        "ward",
        &[
            ("kd".into(), Input::Numbers(vec![0.4, 0.25, 0.1])),
            ("ks".into(), num(0.3)),
            ("alpha_x".into(), num(0.12)),
            ("alpha_y".into(), num(0.35)),
        ],
    )
    .unwrap();
    let table = AnisotropicTabulated::from_model(&truth, [24, 24, 96, 96], false).unwrap();
    let how = TableSampling { count: 6000, strategy: Strategy::HalfDiff, ..TableSampling::default() };
    let s = aniso_table_samples(&table, &how).unwrap();
    let o = FitOptions { tangents: Some(vec![Vec3::X; s.len()]), ..FitOptions::default() };
    let res = fit_model("ward", &s, &o).unwrap();
    let get = |k: &str| res.values.iter().find(|(n, _)| n == k).unwrap().1.clone();
    eprintln!("ward from a 24x24x96x96 table: {:?}, rms log error {:.2e}", res.values, res.rms_log_error);
    let (ax, ay) = (get("alpha_x")[0], get("alpha_y")[0]);
    assert!((ax - 0.12).abs() < 0.01 && (ay - 0.35).abs() < 0.02, "{ax} {ay}");
    for (c, want) in [0.4, 0.25, 0.1].into_iter().enumerate() {
        assert!((get("kd")[c] - want).abs() < 0.02, "{:?}", get("kd"));
    }
    // Without the tangents the frame of +z is the same (+x), and turned tangents swap the two slopes.
    let turned = FitOptions { tangents: Some(vec![Vec3::Y; s.len()]), ..FitOptions::default() };
    let r2 = fit_model("ward", &s, &turned).unwrap();
    let ax2 = r2.values.iter().find(|(n, _)| n == "alpha_x").unwrap().1[0];
    assert!((ax2 - 0.35).abs() < 0.03, "{:?}", r2.values);
    let bad = FitOptions { tangents: Some(vec![Vec3::X; 3]), ..FitOptions::default() };
    assert!(fit_model("ward", &s, &bad).unwrap_err().to_string().starts_with("tangent"));
}

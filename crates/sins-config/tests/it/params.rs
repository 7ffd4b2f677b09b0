//! Parameter files: exact round trips, the coefficient table and the paper's units.

use crate::common;

use common::experiments_dir;
use sins_config::{
    ParamSet, coefficient_table, load_params, params_to_json, params_to_toml, parse_params_json,
    parse_params_toml, write_params,
};
use sins_imu::{ImuErrorParams, ParamModel};

/// Every SI value of a set as raw bits, for bit-exact comparison.
fn bits(p: &ImuErrorParams) -> Vec<u64> {
    let mut v = vec![p.reference_temperature_degc.to_bits()];
    v.extend(
        p.gyro
            .bias_radps
            .iter()
            .chain(p.gyro.scale.iter())
            .map(|x| x.to_bits()),
    );
    v.extend(p.gyro.misalignment_rad.iter().map(|x| x.to_bits()));
    v.extend(
        p.accel
            .bias_mps2
            .iter()
            .chain(p.accel.scale.iter())
            .map(|x| x.to_bits()),
    );
    v.extend(p.accel.misalignment_rad.iter().map(|x| x.to_bits()));
    let t = &p.temperature;
    v.extend(
        t.bias_mps2_per_degc
            .iter()
            .chain(t.scale_per_degc.iter())
            .map(|x| x.to_bits()),
    );
    v.extend(t.misalignment_rad_per_degc.iter().map(|x| x.to_bits()));
    v
}

fn assert_same(a: &ParamSet, b: &ParamSet) {
    assert_eq!(a.params.model, b.params.model);
    assert_eq!(bits(&a.params), bits(&b.params));
    assert_eq!(a.sigma.as_ref().map(bits), b.sigma.as_ref().map(bits));
    assert_eq!(a.description, b.description);
}

#[test]
fn toml_json_toml_round_trip_is_bit_exact() {
    for name in ["paper_table1.toml", "paper_truth.toml", "ideal.toml"] {
        let original =
            load_params(experiments_dir().join("imu").join(name)).unwrap_or_else(|e| panic!("{e}"));
        let json = params_to_json(&original);
        let from_json = parse_params_json(&json, "json").unwrap_or_else(|e| panic!("{e}\n{json}"));
        assert_same(&original, &from_json);
        let toml = params_to_toml(&from_json);
        let from_toml = parse_params_toml(&toml, "toml").unwrap_or_else(|e| panic!("{e}\n{toml}"));
        assert_same(&original, &from_toml);
        // The written numbers are the paper's own (shortest) decimals.
        if name == "paper_table1.toml" {
            assert!(toml.contains("dM_yx_arcsec = -61.88\n"), "{toml}");
            assert!(toml.contains("B_x_deg_per_h = 0.003\n"), "{toml}");
            assert!(json.contains("\"TM_yz_arcsec_per_degc\": -0.6"), "{json}");
        }
    }
}

/// xorshift64* so the test needs no RNG crate.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// A random double of random sign with magnitude in [scale·1e-3, scale·1e3) and random low bits.
    fn value(&mut self, scale: f64) -> f64 {
        let u = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        let x = scale * 10f64.powf(6.0 * u - 3.0);
        let x = f64::from_bits(x.to_bits() ^ (self.next() & 0xff));
        if self.next() & 1 == 1 { -x } else { x }
    }
}

fn random_params(rng: &mut Rng, model: ParamModel) -> ImuErrorParams {
    let mut p = ImuErrorParams::ideal(model);
    // Within the plausible -60..125 degC (magnitudes 5e-5..50 degC).
    p.reference_temperature_degc = rng.value(0.05);
    for i in 0..3 {
        p.gyro.bias_radps[i] = rng.value(1e-8);
        p.gyro.scale[i] = rng.value(1e-5);
        p.gyro.misalignment_rad[i] = rng.value(1e-4);
        p.accel.bias_mps2[i] = rng.value(1e-5);
        p.accel.scale[i] = rng.value(1e-5);
        if model == ParamModel::States42 {
            p.temperature.bias_mps2_per_degc[i] = rng.value(1e-5);
            p.temperature.scale_per_degc[i] = rng.value(1e-5);
        }
    }
    for i in 0..6 {
        p.accel.misalignment_rad[i] = rng.value(1e-4);
        if model == ParamModel::States42 {
            p.temperature.misalignment_rad_per_degc[i] = rng.value(1e-6);
        }
    }
    p
}

#[test]
fn arbitrary_si_values_round_trip_bit_exact() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for round in 0..300 {
        let model = if round % 3 == 0 {
            ParamModel::States30
        } else {
            ParamModel::States42
        };
        let params = random_params(&mut rng, model);
        let sigma = random_params(&mut rng, model);
        let mut sigma_abs = sigma;
        for b in [
            &mut sigma_abs.gyro.bias_radps,
            &mut sigma_abs.accel.bias_mps2,
        ] {
            *b = b.abs();
        }
        sigma_abs.gyro.scale = sigma_abs.gyro.scale.abs();
        sigma_abs.gyro.misalignment_rad = sigma_abs.gyro.misalignment_rad.map(f64::abs);
        sigma_abs.accel.scale = sigma_abs.accel.scale.abs();
        sigma_abs.accel.misalignment_rad = sigma_abs.accel.misalignment_rad.map(f64::abs);
        let t = &mut sigma_abs.temperature;
        t.bias_mps2_per_degc = t.bias_mps2_per_degc.abs();
        t.scale_per_degc = t.scale_per_degc.abs();
        t.misalignment_rad_per_degc = t.misalignment_rad_per_degc.map(f64::abs);
        sigma_abs.reference_temperature_degc = params.reference_temperature_degc;
        let set = ParamSet {
            params,
            sigma: Some(sigma_abs),
            description: format!("round {round}: \"quoted\" \\ and unicode °"),
        };
        let toml = params_to_toml(&set);
        let back = parse_params_toml(&toml, "t").unwrap_or_else(|e| panic!("{e}\n{toml}"));
        assert_same(&set, &back);
        let json = params_to_json(&set);
        let back = parse_params_json(&json, "j").unwrap_or_else(|e| panic!("{e}\n{json}"));
        assert_same(&set, &back);
    }
}

#[test]
fn negative_zero_and_integers_survive() {
    let mut p = ImuErrorParams::ideal(ParamModel::States30);
    p.gyro.scale.x = -0.0;
    p.accel.bias_mps2.y = 3.0 * 9.80665e-6;
    let set = ParamSet::from(p);
    let back = parse_params_toml(&params_to_toml(&set), "t").unwrap_or_else(|e| panic!("{e}"));
    assert_same(&set, &back);
    assert!(back.params.gyro.scale.x.is_sign_negative());
}

#[test]
fn write_params_chooses_format_by_extension() {
    let set = load_params(experiments_dir().join("imu/paper_truth.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().expect("temp dir");
    for name in ["out.json", "out.toml", "OUT.JSON"] {
        let path = dir.path().join(name);
        write_params(&path, &set).unwrap_or_else(|e| panic!("{e}"));
        let text = std::fs::read_to_string(&path).expect("written");
        assert_eq!(
            text.trim_start().starts_with('{'),
            name.to_lowercase().ends_with(".json"),
            "{name}"
        );
        assert_same(&set, &load_params(&path).unwrap_or_else(|e| panic!("{e}")));
    }
    let err = write_params(dir.path().join("out.yaml"), &set).expect_err("yaml is not a format");
    assert!(err.to_string().contains("out.yaml"), "{err}");
}

#[test]
fn coefficient_table_follows_eq_8() {
    let set = load_params(experiments_dir().join("imu/paper_table1.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let table = coefficient_table(&set.params);
    let names: Vec<&str> = table.iter().map(|c| c.name).collect();
    assert_eq!(
        names,
        [
            "B_gx", "B_gy", "B_gz", "B_ax", "B_ay", "B_az", "dK_gx", "dM_gyx", "dM_gzx", "dK_gy",
            "dM_gzy", "dK_gz", "dK_ax", "dM_ayx", "dM_azx", "dM_axy", "dK_ay", "dM_azy", "dM_axz",
            "dM_ayz", "dK_az", "TB_ax", "TB_ay", "TB_az", "TK_ax", "TK_ay", "TK_az", "TM_ayx",
            "TM_azx", "TM_axy", "TM_azy", "TM_axz", "TM_ayz",
        ]
    );
    // Values and units against the paper's Table 1 CSV (name,unit,preset,...).
    let csv = std::fs::read_to_string("/work/shared/paper/table1_simulation.csv").ok();
    let expected: Vec<(String, String, f64)> = match csv {
        Some(text) => text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (
                    f[0].to_owned(),
                    f[1].to_owned(),
                    f[2].parse().expect("preset"),
                )
            })
            .collect(),
        None => vec![
            ("B_gx".into(), "deg/h".into(), 0.003),
            ("TM_ayz".into(), "arcsec/degC".into(), -0.6),
        ],
    };
    for (name, unit, value) in expected {
        let c = table
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("{name} missing"));
        assert_eq!(c.unit, unit, "{name}");
        assert!(
            (c.value - value).abs() <= 1e-12 * value.abs().max(1.0),
            "{name}: {} vs {value}",
            c.value
        );
    }
    let mut p30 = set.params;
    p30.model = ParamModel::States30;
    assert_eq!(coefficient_table(&p30).len(), 21);
}

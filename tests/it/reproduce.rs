//! `isola reproduce --quick --json`: every claim of the paper present, with a finite value,
//! precision and a verdict, and the verdicts that a careful computation settles checked
//! against bands that can fail.

use crate::common::json;

/// The claims `reproduce` must always report.
const CLAIMS: [&str; 24] = [
    "drive-components",
    "drive-field",
    "coexist-adr06-w37",
    "tenfold-adr06-w37",
    "basin-fig6a",
    "coexist-adr06-w18",
    "coexist-adr06-w12",
    "coexist-adr10-w36",
    "basin-fig6b",
    "coexist-adr10-w37",
    "isola-adr06",
    "sweep-adr06",
    "attached-adr10",
    "sweep-adr10",
    "isola-1to3-range",
    "isola-birth-adr",
    "isola-merge-adr",
    "isola-1to3-birth-adr",
    "vanish-damping",
    "vanish-prestretch",
    "collision-ea",
    "fig11a-retriggered",
    "fig11b-retriggered",
    "fig12-no-subharmonic",
];

#[test]
fn reproduce_quick_reports_every_claim_with_a_verdict() {
    let started = std::time::Instant::now();
    let v = json(&["reproduce", "--quick", "--json"]);
    eprintln!(
        "reproduce --quick: {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert_eq!(v["mode"], "quick");
    let claims = v["claims"].as_array().expect("a list of claims");
    let ids: Vec<&str> = claims.iter().map(|c| c["id"].as_str().unwrap()).collect();
    assert_eq!(ids, CLAIMS, "{v}");
    for c in claims {
        for key in ["value", "precision"] {
            let x = c[key].as_f64().unwrap_or(f64::NAN);
            assert!(x.is_finite() && (key == "value" || x >= 0.0), "{key}: {c}");
        }
        let verdict = c["verdict"].as_str().unwrap();
        assert!(["agrees", "differs", "imprecise"].contains(&verdict), "{c}");
        for key in ["figure", "paper", "isola", "precision_from", "note"] {
            assert!(!c[key].as_str().unwrap().is_empty(), "{key}: {c}");
        }
    }
    let claim = |id: &str| claims.iter().find(|c| c["id"] == id).unwrap();
    let value = |id: &str| claim(id)["value"].as_f64().unwrap();
    let verdict = |id: &str| claim(id)["verdict"].as_str().unwrap().to_string();
    // the isola is born well below the paper's 0.25 (located on its fold curve)
    assert!((value("isola-birth-adr") - 0.2064).abs() < 1e-3);
    assert!(claim("isola-birth-adr")["precision"].as_f64().unwrap() < 1e-6);
    assert_eq!(verdict("isola-birth-adr"), "differs");
    // and merges where the paper says, to its two decimals
    assert!((value("isola-merge-adr") - 0.645260).abs() < 1e-5);
    // located on the fold curve the attached branch gains there, not just bracketed (the
    // fold curve's points solve its test function to 1e-8: about 4e-8 in ADR there)
    assert!(claim("isola-merge-adr")["precision"].as_f64().unwrap() <= 1e-7);
    assert_eq!(verdict("isola-merge-adr"), "agrees");
    // the ADR 0.6 isola's lower fold, and the narrow period-3 isola below the paper's band
    assert!((value("isola-adr06") - 3.589644726).abs() < 1e-8);
    assert_eq!(verdict("isola-adr06"), "agrees");
    assert!((value("isola-1to3-range") - 3.5387).abs() < 1e-3);
    assert_eq!(verdict("isola-1to3-range"), "differs");
    assert!((claim("isola-1to3-range")["difference"].as_f64().unwrap() + 0.111).abs() < 2e-3);
    assert_eq!(verdict("attached-adr10"), "agrees");
    // the isola vanishes with pre-stretch at the fold curve's maximum
    assert!((value("vanish-prestretch") - 1.0480627675).abs() < 1e-8);
    // stable responses first reach a frame at √E_a ≈ 0.274 (full run: 0.2743 ± 2e-4): the
    // paper's "below 0.25²" holds, conservatively
    assert!((value("collision-ea").sqrt() - 0.2743).abs() < 0.01);
    assert_eq!(verdict("collision-ea"), "imprecise");
    // the responses of Figs 4 and 5
    assert_eq!(value("coexist-adr06-w37"), 2.0);
    assert!(value("tenfold-adr06-w37") > 10.0);
    assert_eq!(verdict("tenfold-adr06-w37"), "agrees");
    assert_eq!(value("coexist-adr10-w36"), 3.0);
    assert_eq!(verdict("fig12-no-subharmonic"), "agrees");
    let counts: u64 = ["agrees", "differs", "imprecise"]
        .iter()
        .map(|k| v[k].as_u64().unwrap())
        .sum();
    assert_eq!(counts as usize, claims.len());
}

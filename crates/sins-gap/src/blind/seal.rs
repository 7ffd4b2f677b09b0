//! Sealed manifests: each case's answer in its own file, their SHA-256 hashes fixed in an
//! index before any diagnosis runs, checked again before grading.

use super::plan::CaseAnswer;
use crate::GapError;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The index of a sealed suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SealIndex {
    /// Suite seed.
    pub suite_seed: u64,
    /// (case, SHA-256 of its manifest file, hex).
    pub manifests: Vec<(String, String)>,
    /// SHA-256 of the concatenated manifest hashes: one figure that fixes the whole suite.
    pub suite_sha256: String,
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn sha256(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// The directory of the sealed manifests.
pub fn sealed_dir(out: &Path) -> PathBuf {
    out.join("sealed")
}

/// Write every answer to `<out>/sealed/<case>.json` and the hashes to
/// `<out>/sealed/index.json`; returns the index.
pub fn seal(out: &Path, suite_seed: u64, answers: &[CaseAnswer]) -> Result<SealIndex, GapError> {
    let dir = sealed_dir(out);
    std::fs::create_dir_all(&dir).map_err(|e| GapError::io(&dir, e))?;
    let mut manifests = Vec::new();
    let mut all = String::new();
    for a in answers {
        let text = serde_json::to_string_pretty(a)
            .map_err(|e| GapError::Invalid(format!("manifest of {}: {e}", a.case)))?;
        let path = dir.join(format!("{}.json", a.case));
        std::fs::write(&path, &text).map_err(|e| GapError::io(&path, e))?;
        let h = sha256(text.as_bytes());
        all.push_str(&h);
        manifests.push((a.case.clone(), h));
    }
    let index = SealIndex {
        suite_seed,
        manifests,
        suite_sha256: sha256(all.as_bytes()),
    };
    let path = dir.join("index.json");
    let text = serde_json::to_string_pretty(&index)
        .map_err(|e| GapError::Invalid(format!("seal index: {e}")))?;
    std::fs::write(&path, text).map_err(|e| GapError::io(&path, e))?;
    Ok(index)
}

/// Open the manifests after the diagnoses: each must hash to the value fixed in `index`.
pub fn open(out: &Path, index: &SealIndex) -> Result<Vec<CaseAnswer>, GapError> {
    let dir = sealed_dir(out);
    index
        .manifests
        .iter()
        .map(|(case, want)| {
            let path = dir.join(format!("{case}.json"));
            let text = std::fs::read_to_string(&path).map_err(|e| GapError::io(&path, e))?;
            let got = sha256(text.as_bytes());
            if &got != want {
                return Err(GapError::Invalid(format!(
                    "{}: the manifest changed after sealing (SHA-256 {got}, sealed {want})",
                    path.display()
                )));
            }
            serde_json::from_str(&text)
                .map_err(|e| GapError::Invalid(format!("{}: {e}", path.display())))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blind::plan::{SuiteShape, draw_cases};

    #[test]
    fn sealed_manifests_round_trip_and_tampering_is_caught() {
        let dir = tempfile::tempdir().unwrap();
        let answers = draw_cases(&SuiteShape::default(), 3);
        let index = seal(dir.path(), 3, &answers).unwrap();
        assert_eq!(open(dir.path(), &index).unwrap(), answers);
        let p = sealed_dir(dir.path()).join("case05.json");
        let text = std::fs::read_to_string(&p).unwrap();
        std::fs::write(&p, text.replace("\"seed\"", "\"seed\" ")).unwrap();
        let e = open(dir.path(), &index).unwrap_err().to_string();
        assert!(
            e.contains("case05.json") && e.contains("changed after sealing"),
            "{e}"
        );
    }
}

//! Validation context of one experiment file: builds errors that name the file, the key path and
//! its line, checks numbers, and resolves and reads referenced files.

use crate::error::{ConfigError, line_of};
use crate::plausible::MAX_RUN_DURATION_S;
use std::path::{Path, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Context for semantic checks of one TOML file.
pub(crate) struct Ctx<'a> {
    /// The file, as shown in errors.
    pub(crate) origin: String,
    /// Directory relative paths are resolved against.
    pub(crate) dir: PathBuf,
    src: &'a str,
    doc: Option<Spanned<DeTable<'a>>>,
}

impl<'a> Ctx<'a> {
    /// A context for `src` read from `path`.
    pub(crate) fn new(path: &Path, src: &'a str) -> Self {
        Self {
            origin: path.display().to_string(),
            dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            src,
            doc: DeTable::parse(src).ok(),
        }
    }

    /// The line of the key at dotted `path` (`motion.segment[3].duration_s`), or of its deepest
    /// existing ancestor when the key itself is absent.
    pub(crate) fn line(&self, path: &str) -> Option<usize> {
        let doc = self.doc.as_ref()?;
        let mut table: &DeTable<'_> = doc.get_ref();
        let mut line = None;
        for part in path.split('.') {
            let (name, indices) = match part.find('[') {
                Some(i) => (&part[..i], &part[i..]),
                None => (part, ""),
            };
            let Some((key, value)) = table.iter().find(|(k, _)| k.get_ref() == name) else {
                return line;
            };
            line = Some(line_of(self.src, key.span().start));
            let mut value: &Spanned<DeValue<'_>> = value;
            for index in indices.split('[').filter(|s| !s.is_empty()) {
                let Some(i) = index.trim_end_matches(']').parse::<usize>().ok() else {
                    return line;
                };
                let Some(item) = value.get_ref().as_array().and_then(|a| a.get(i)) else {
                    return line;
                };
                line = Some(line_of(self.src, item.span().start));
                value = item;
            }
            match value.get_ref() {
                DeValue::Table(t) => table = t,
                _ => return line,
            }
        }
        line
    }

    /// An [`ConfigError::Invalid`] for `key` with its line.
    pub(crate) fn invalid(&self, key: &str, problem: impl Into<String>) -> ConfigError {
        ConfigError::Invalid {
            origin: self.origin.clone(),
            line: self.line(key),
            key: key.to_owned(),
            problem: problem.into(),
        }
    }

    /// A [`ConfigError::MissingKey`] for `key`.
    pub(crate) fn missing(&self, key: &str, note: impl Into<String>) -> ConfigError {
        ConfigError::MissingKey {
            origin: self.origin.clone(),
            key: key.to_owned(),
            note: note.into(),
        }
    }

    /// `v` if finite.
    pub(crate) fn finite(&self, key: &str, v: f64) -> Result<f64, ConfigError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.invalid(key, format!("must be a finite number, got {v}")))
        }
    }

    /// `v` if finite and > 0.
    pub(crate) fn positive(&self, key: &str, v: f64) -> Result<f64, ConfigError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, format!("must be a positive finite number, got {v}")))
        }
    }

    /// `v` if finite and >= 0.
    pub(crate) fn non_negative(&self, key: &str, v: f64) -> Result<f64, ConfigError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, format!("must be a finite number >= 0, got {v}")))
        }
    }

    /// Each element finite.
    pub(crate) fn finite3(&self, key: &str, v: [f64; 3]) -> Result<[f64; 3], ConfigError> {
        for (i, x) in v.iter().enumerate() {
            self.finite(&format!("{key}[{i}]"), *x)?;
        }
        Ok(v)
    }

    /// A duration in seconds from exactly one of `<prefix>.duration_s` / `<prefix>.duration_h`,
    /// required to be positive, finite and at most [`MAX_RUN_DURATION_S`].
    pub(crate) fn duration(
        &self,
        prefix: &str,
        seconds: Option<f64>,
        hours: Option<f64>,
    ) -> Result<f64, ConfigError> {
        let at_most = |key: String, d_s: f64| {
            if d_s > MAX_RUN_DURATION_S {
                let msg = format!(
                    "{d_s} s is longer than the {MAX_RUN_DURATION_S} s (366 days) a run may last"
                );
                Err(self.invalid(&key, msg))
            } else {
                Ok(d_s)
            }
        };
        match (seconds, hours) {
            (Some(s), None) => {
                let key = format!("{prefix}.duration_s");
                at_most(key.clone(), self.positive(&key, s)?)
            }
            (None, Some(h)) => {
                let key = format!("{prefix}.duration_h");
                at_most(key.clone(), self.positive(&key, h)? * 3600.0)
            }
            (Some(_), Some(_)) => Err(self.invalid(
                prefix,
                "give exactly one of `duration_s` and `duration_h`, not both",
            )),
            (None, None) => Err(self.missing(
                &format!("{prefix}.duration_s"),
                "give exactly one of `duration_s` and `duration_h`",
            )),
        }
    }

    /// Resolves `rel` (relative to the experiment file's directory) and reads it as text; a
    /// missing or unreadable file is a [`ConfigError::MissingReference`] naming `key` and the path.
    pub(crate) fn read_referenced(
        &self,
        key: &str,
        rel: &str,
    ) -> Result<(PathBuf, String), ConfigError> {
        let path = self.dir.join(rel);
        match std::fs::read_to_string(&path) {
            Ok(text) => Ok((path, text)),
            Err(source) => Err(ConfigError::MissingReference {
                origin: self.origin.clone(),
                line: self.line(key),
                key: key.to_owned(),
                path,
                source,
            }),
        }
    }

    /// Wraps an error from a referenced file.
    pub(crate) fn referenced(&self, key: &str, source: ConfigError) -> ConfigError {
        ConfigError::Referenced {
            origin: self.origin.clone(),
            key: key.to_owned(),
            source: Box::new(source),
        }
    }
}

/// An array element whose deserialization is deferred so that an error in it can name its index:
/// the toml crate reports errors inside internally tagged tables at the start of the array.
#[derive(Clone, Debug)]
pub(crate) struct Deferred<T>(Result<T, String>);

impl<'de, T: serde::de::DeserializeOwned> serde::Deserialize<'de> for Deferred<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(d)?;
        Ok(Deferred(
            T::deserialize(value).map_err(|e| e.message().trim().to_owned()),
        ))
    }
}

impl<T> Deferred<T> {
    /// The element, or a [`ConfigError::Parse`] naming `key` (e.g. `motion.segment[2]`) and its line.
    pub(crate) fn get(&self, ctx: &Ctx<'_>, key: &str) -> Result<&T, ConfigError> {
        self.0.as_ref().map_err(|message| ConfigError::Parse {
            origin: ctx.origin.clone(),
            line: ctx.line(key),
            column: None,
            key: Some(key.to_owned()),
            message: message.clone(),
        })
    }
}

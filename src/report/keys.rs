//! What the keys of an experiment file mean, for the "Problem solved" table of each section:
//! `text/keys.toml`, one short phrase per key under the table it is in, compiled into the
//! binary and read at first use (the test `every_shipped_key_is_explained` keeps every key of
//! the shipped experiment files and templates covered).

use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The keys file as shipped.
const KEYS_TOML: &str = include_str!("text/keys.toml");

type Keys = BTreeMap<String, BTreeMap<String, String>>;

fn keys() -> &'static Keys {
    static KEYS: OnceLock<Keys> = OnceLock::new();
    KEYS.get_or_init(|| {
        // Checked by the tests: a broken file fails them, it does not reach a user.
        toml::from_str(KEYS_TOML).unwrap_or_else(|e| panic!("src/report/text/keys.toml: {e}"))
    })
}

/// The meaning of `key` in the parameter group `group` (`scene`, `scene.reynolds`, `study`):
/// looked up under the group's last part.
pub fn meaning(group: &str, key: &str) -> Option<&'static str> {
    let table = group.rsplit('.').next().unwrap_or(group);
    keys().get(table)?.get(key).map(String::as_str)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::parameters;

    #[test]
    fn every_shipped_key_is_explained() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
        let mut files = 0;
        for dir in [root.clone(), root.join("templates")] {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "toml") {
                    files += 1;
                    let text = std::fs::read_to_string(&path).unwrap();
                    for p in parameters::of_file(&text) {
                        assert!(
                            meaning(&p.group, &p.key).is_some(),
                            "{}: [{}] {} has no meaning in text/keys.toml",
                            path.display(),
                            p.group,
                            p.key
                        );
                    }
                }
            }
        }
        assert!(files > 80, "{files}");
        assert_eq!(meaning("scene.reynolds", "gap"), meaning("reynolds", "gap"));
        assert!(meaning("study", "no-such-key").is_none());
    }
}

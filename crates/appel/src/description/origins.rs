//! Where the parts of a converted description were written. A reader that converts another format
//! (Mitsuba XML, pbrt) into a [`Description`](super::Description) records, for each entry it
//! makes (`shape[3]`, `materials.glass`, `camera`...), the place of the element or directive that
//! made it and of that element's parameters, so that a problem only the validation of the
//! description finds is reported at the line it comes from.

use super::parse::PathSeg;
use crate::error::Location;

/// The place of one source element, and of its parameters by the description's key they fill.
#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    pub at: Location,
    pub parts: Vec<(String, Location)>,
}

impl Origin {
    /// A place without parameters of its own.
    pub fn at(at: Location) -> Self {
        Self {
            at,
            parts: Vec::new(),
        }
    }

    /// The place of the parameter filling `key`.
    pub fn part(&self, key: &str) -> Option<&Location> {
        self.parts.iter().find(|(k, _)| k == key).map(|(_, at)| at)
    }
}

/// Description key paths and where they were written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Origins {
    entries: Vec<(Vec<PathSeg>, Origin)>,
}

impl Origins {
    /// Records that the description's entry at `path` was made by `origin`. A later record of the
    /// same path replaces the earlier one.
    pub fn record(&mut self, path: Vec<PathSeg>, origin: Origin) {
        self.entries.retain(|(p, _)| *p != path);
        self.entries.push((path, origin));
    }

    /// Where the value at `path` was written: the entry recorded with the longest prefix of
    /// `path` and, where the key after that prefix is one of its parts, that part's place.
    pub fn locate(&self, path: &[PathSeg]) -> Option<&Location> {
        let (prefix, origin) = self
            .entries
            .iter()
            .filter(|(p, _)| path.starts_with(p))
            .max_by_key(|(p, _)| p.len())?;
        let part = match path.get(prefix.len()) {
            Some(PathSeg::Key(k)) => origin.part(k),
            _ => None,
        };
        Some(part.unwrap_or(&origin.at))
    }
}

/// `["shape", 3]` and the like, for [`Origins::record`].
pub fn key_path(segments: &[&dyn AsSegment]) -> Vec<PathSeg> {
    segments.iter().map(|s| s.segment()).collect()
}

/// A key (`&str`) or an index (`usize`) of a description path.
pub trait AsSegment {
    fn segment(&self) -> PathSeg;
}

impl AsSegment for &str {
    fn segment(&self) -> PathSeg {
        PathSeg::Key(self.to_string())
    }
}

impl AsSegment for String {
    fn segment(&self) -> PathSeg {
        PathSeg::Key(self.clone())
    }
}

impl AsSegment for usize {
    fn segment(&self) -> PathSeg {
        PathSeg::Index(*self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: usize) -> Location {
        Location::line("scene.xml", line, Some(1))
    }

    #[test]
    fn the_longest_prefix_and_its_part_win() {
        let mut o = Origins::default();
        o.record(
            key_path(&[&"shape", &2usize]),
            Origin {
                at: at(10),
                parts: vec![("radius".into(), at(11))],
            },
        );
        o.record(
            key_path(&[&"shape", &2usize, &"emitter"]),
            Origin {
                at: at(12),
                parts: vec![("radiance".into(), at(13))],
            },
        );
        o.record(
            key_path(&[&"camera"]),
            Origin {
                at: at(3),
                parts: vec![],
            },
        );
        let line = |p: &[&dyn AsSegment]| o.locate(&key_path(p)).and_then(|l| l.line);
        assert_eq!(line(&[&"shape", &2usize, &"radius"]), Some(11));
        assert_eq!(line(&[&"shape", &2usize, &"center"]), Some(10));
        assert_eq!(
            line(&[&"shape", &2usize, &"emitter", &"radiance"]),
            Some(13)
        );
        assert_eq!(line(&[&"shape", &2usize, &"emitter"]), Some(12));
        assert_eq!(line(&[&"camera", &"fov"]), Some(3));
        assert_eq!(line(&[&"shape", &1usize, &"radius"]), None);
        assert_eq!(line(&[&"light", &0usize]), None);
    }

    #[test]
    fn a_later_record_of_a_path_replaces_the_earlier() {
        let mut o = Origins::default();
        let p = key_path(&[&"materials", &"glass"]);
        for line in [4, 9] {
            o.record(
                p.clone(),
                Origin {
                    at: at(line),
                    parts: vec![],
                },
            );
        }
        assert_eq!(o.locate(&p).and_then(|l| l.line), Some(9));
    }
}

//! Stitch patterns of weft knits (SPEC §9.3): a grid of knit and purl
//! stitches, course j = 0 at the bottom (cast on first), wale i = 0 on the
//! left as seen from the front (+z). A knit stitch pulls its loop through
//! the loop below towards the front, a purl towards the back.
use strandkit_core::{Error, Result};

/// Most stitches a fabric may have (Cirio et al.'s sweater has 56K loops).
pub const MAX_STITCHES: usize = 200_000;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stitch {
    Knit,
    Purl,
}

impl Stitch {
    /// +1 for knit, −1 for purl: the side (front +z) the loop is pulled to.
    pub fn sign(self) -> f64 {
        match self {
            Stitch::Knit => 1.0,
            Stitch::Purl => -1.0,
        }
    }
}

/// The named patterns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// Plain jersey (stockinette): every stitch knit.
    Jersey,
    /// 1×1 rib: knit and purl wales alternate.
    Rib1x1,
    /// 2×2 rib: two knit wales, two purl wales.
    Rib2x2,
    /// Garter: knit and purl courses alternate.
    Garter,
    /// Seed (moss): knit and purl alternate along both directions.
    Seed,
}

impl Pattern {
    pub const NAMES: [&'static str; 5] = ["jersey", "rib1x1", "rib2x2", "garter", "seed"];

    pub fn from_name(name: &str) -> Result<Pattern> {
        Ok(match name.to_ascii_lowercase().as_str() {
            "jersey" | "stockinette" => Pattern::Jersey,
            "rib1x1" => Pattern::Rib1x1,
            "rib2x2" => Pattern::Rib2x2,
            "garter" => Pattern::Garter,
            "seed" | "moss" => Pattern::Seed,
            _ => return Err(Error::invalid("pattern", name, format!("one of {}, or a stitch grid", Pattern::NAMES.join(", ")))),
        })
    }

    fn stitch(self, i: usize, j: usize) -> Stitch {
        let knit = match self {
            Pattern::Jersey => true,
            Pattern::Rib1x1 => i % 2 == 0,
            Pattern::Rib2x2 => i % 4 < 2,
            Pattern::Garter => j % 2 == 0,
            Pattern::Seed => (i + j) % 2 == 0,
        };
        if knit {
            Stitch::Knit
        } else {
            Stitch::Purl
        }
    }
}

/// A rectangular grid of stitches, `wales` × `courses`.
#[derive(Clone, Debug, PartialEq)]
pub struct StitchGrid {
    wales: usize,
    courses: usize,
    /// Course-major: stitch (i, j) at j·wales + i.
    stitches: Vec<Stitch>,
}

impl StitchGrid {
    /// A named pattern on `wales` × `courses` stitches.
    pub fn new(pattern: Pattern, wales: usize, courses: usize) -> Result<StitchGrid> {
        check_size(wales, courses)?;
        let stitches = (0..courses).flat_map(|j| (0..wales).map(move |i| pattern.stitch(i, j))).collect();
        Ok(StitchGrid { wales, courses, stitches })
    }

    /// A custom grid: one string per course, bottom course first, one
    /// letter per stitch, 'K' (knit) or 'P' (purl), case-insensitive. Every
    /// course must have as many stitches as the first: a stitch needs the
    /// loop below it (no increases or decreases).
    pub fn parse(courses: &[&str]) -> Result<StitchGrid> {
        let wales = courses.first().map(|c| c.chars().count()).unwrap_or(0);
        check_size(wales, courses.len())?;
        let mut stitches = Vec::with_capacity(wales * courses.len());
        for (j, row) in courses.iter().enumerate() {
            let n = row.chars().count();
            if n != wales {
                return Err(Error::invalid(
                    format!("stitch grid course {j}"),
                    format!("{n} stitches"),
                    format!("{wales} like course 0: every stitch is pulled through the loop below it (no increases, decreases or holes)"),
                ));
            }
            for (i, ch) in row.chars().enumerate() {
                stitches.push(match ch.to_ascii_uppercase() {
                    'K' => Stitch::Knit,
                    'P' => Stitch::Purl,
                    other => {
                        return Err(Error::invalid(format!("stitch grid course {j}, wale {i}"), format!("{other:?}"), "'K' (knit) or 'P' (purl)"))
                    }
                });
            }
        }
        Ok(StitchGrid { wales, courses: courses.len(), stitches })
    }

    pub fn wales(&self) -> usize {
        self.wales
    }
    pub fn courses(&self) -> usize {
        self.courses
    }
    pub fn get(&self, i: usize, j: usize) -> Stitch {
        self.stitches[j * self.wales + i]
    }
    /// The grid as strings, bottom course first (the inverse of `parse`).
    pub fn rows(&self) -> Vec<String> {
        (0..self.courses)
            .map(|j| (0..self.wales).map(|i| if self.get(i, j) == Stitch::Knit { 'K' } else { 'P' }).collect())
            .collect()
    }
}

fn check_size(wales: usize, courses: usize) -> Result<()> {
    if wales == 0 {
        return Err(Error::invalid("wales", wales, "at least 1"));
    }
    if courses < 2 {
        return Err(Error::invalid("courses", courses, "at least 2 (a loop is held by the loop through it)"));
    }
    match wales.checked_mul(courses) {
        Some(n) if n <= MAX_STITCHES => Ok(()),
        _ => Err(Error::invalid("wales × courses", format!("{wales} × {courses}"), format!("at most {MAX_STITCHES} stitches"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_place_knit_and_purl() {
        let rib = StitchGrid::new(Pattern::Rib2x2, 8, 2).unwrap();
        assert_eq!(rib.rows(), vec!["KKPPKKPP", "KKPPKKPP"]);
        let seed = StitchGrid::new(Pattern::Seed, 4, 3).unwrap();
        assert_eq!(seed.rows(), vec!["KPKP", "PKPK", "KPKP"]);
        let garter = StitchGrid::new(Pattern::Garter, 3, 3).unwrap();
        assert_eq!(garter.rows(), vec!["KKK", "PPP", "KKK"]);
        assert_eq!(StitchGrid::parse(&["kpP", "KKK"]).unwrap().rows(), vec!["KPP", "KKK"]);
    }

    #[test]
    fn grids_that_cannot_be_knitted_are_refused() {
        for (grid, what) in [
            (StitchGrid::parse(&["KK", "K"]), "course 1"),
            (StitchGrid::parse(&["KX", "KK"]), "wale 1"),
            (StitchGrid::parse(&["", ""]), "wales"),
            (StitchGrid::parse(&["KK"]), "courses"),
            (StitchGrid::new(Pattern::Jersey, 0, 4), "wales"),
            (StitchGrid::new(Pattern::Jersey, 100_000, 100_000), "at most"),
        ] {
            let e = grid.unwrap_err().to_string();
            assert!(e.contains(what), "{e}");
        }
        assert!(Pattern::from_name("tweed").unwrap_err().to_string().contains("jersey"));
    }
}

//! A frame of an extended XYZ file: this project's columns (`id species pos velo radius
//! omega image`) and OVITO's and ASE's names for them. The comment line's `Lattice`
//! (orthogonal), `Origin` and `pbc` give the box; without a `Lattice` there is none.

use super::{FileState, Row, file_box, frame_index};
use crate::error::{Result, invalid};

/// The columns read, each by the names it goes by (compared ignoring case, spaces and
/// underscores).
const COLUMNS: [(&str, &[&str]); 8] = [
    ("id", &["id", "particleidentifier"]),
    (
        "type",
        &["species", "type", "particletype", "element", "typeid"],
    ),
    ("position", &["pos", "position", "positions"]),
    ("velocity", &["velo", "vel", "velocity", "velocities"]),
    ("radius", &["radius", "radii"]),
    ("mass", &["mass", "masses"]),
    ("angular_velocity", &["omega", "angularvelocity"]),
    ("image", &["image", "periodicimage"]),
];

/// Where each column starts in a row (and its width).
#[derive(Default)]
struct Layout {
    at: [Option<(usize, usize)>; 8],
    width: usize,
}

fn canonical(name: &str) -> String {
    name.chars()
        .filter(|c| !matches!(c, ' ' | '_' | '.'))
        .flat_map(char::to_lowercase)
        .collect()
}

/// The `key=value` fields of a comment line (values quoted or bare).
fn fields(line: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = line.trim();
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].trim().to_string();
        let after = rest[eq + 1..].trim_start();
        let (value, tail) = if let Some(q) = after.strip_prefix('"') {
            match q.find('"') {
                Some(end) => (&q[..end], &q[end + 1..]),
                None => (q, ""),
            }
        } else {
            match after.find(char::is_whitespace) {
                Some(end) => (&after[..end], &after[end..]),
                None => (after, ""),
            }
        };
        // A key may follow words without '=' (free text): keep its last word.
        let key = key.rsplit(char::is_whitespace).next().unwrap_or_default();
        out.push((key.to_string(), value.to_string()));
        rest = tail;
    }
    out
}

fn layout(properties: &str) -> Result<Layout> {
    let parts: Vec<&str> = properties.split(':').collect();
    if parts.len() % 3 != 0 {
        return invalid!("Properties=\"{properties}\" is not name:type:count triples");
    }
    let mut l = Layout::default();
    for p in parts.chunks(3) {
        let Ok(count) = p[2].parse::<usize>() else {
            return invalid!(
                "Properties: column {} has count '{}', not a number",
                p[0],
                p[2]
            );
        };
        let name = canonical(p[0]);
        if let Some(c) = COLUMNS
            .iter()
            .position(|(_, names)| names.contains(&name.as_str()))
        {
            l.at[c] = Some((l.width, count));
        }
        l.width += count;
    }
    Ok(l)
}

fn numbers<const N: usize>(
    words: &[&str],
    at: Option<(usize, usize)>,
    what: &str,
    line: usize,
) -> Result<Option<[f64; N]>> {
    let Some((start, count)) = at else {
        return Ok(None);
    };
    if count != N {
        return invalid!("column {what} has {count} entries per row where {N} were expected");
    }
    let mut v = [0.0; N];
    for k in 0..N {
        v[k] = match words[start + k].parse::<f64>() {
            Ok(x) => x,
            Err(_) => {
                return invalid!("line {line}: {what} '{}' is not a number", words[start + k]);
            }
        };
    }
    Ok(Some(v))
}

/// Frame `frame` (negative from the end) of the extended XYZ text.
pub(super) fn read(text: &str, frame: i64) -> Result<FileState> {
    let lines: Vec<&str> = text.lines().collect();
    // Where each frame starts.
    let mut starts = Vec::new();
    let mut at = 0;
    while at < lines.len() {
        if lines[at].trim().is_empty() {
            at += 1;
            continue;
        }
        let Ok(n) = lines[at].trim().parse::<usize>() else {
            return invalid!(
                "line {}: '{}' should be the particle count of a frame",
                at + 1,
                lines[at].trim()
            );
        };
        if at + 2 + n > lines.len() {
            return invalid!(
                "the frame at line {} announces {n} particles but the file ends before them \
                 (cut short?)",
                at + 1
            );
        }
        starts.push(at);
        at += 2 + n;
    }
    let f = frame_index(frame, starts.len())?;
    let start = starts[f];
    let n: usize = lines[start].trim().parse().expect("checked");
    let comment = fields(lines[start + 1]);
    let get = |key: &str| {
        comment
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(key))
            .map(|(_, v)| v.as_str())
    };
    let Some(properties) = get("Properties") else {
        return invalid!(
            "frame {f} has no Properties=… on its comment line: this reads extended XYZ \
             (species:S:1:pos:R:3:…)"
        );
    };
    let l = layout(properties)?;
    let [id, ty, pos, vel, radius, mass, omega, image] = l.at;
    if pos.is_none() {
        return invalid!("missing column: Properties=\"{properties}\" has no pos (positions)");
    }
    if radius.is_none() {
        return invalid!(
            "missing column: Properties=\"{properties}\" has no radius; add a radius column"
        );
    }
    let mut rows = Vec::with_capacity(n);
    let mut ids = Vec::with_capacity(n);
    for i in 0..n {
        let line_no = start + 3 + i;
        let words: Vec<&str> = lines[start + 2 + i].split_whitespace().collect();
        if words.len() < l.width {
            return invalid!(
                "line {line_no} has {} entries where Properties gives {}",
                words.len(),
                l.width
            );
        }
        let type_name = ty.map_or("0".to_string(), |(s, _)| words[s].to_string());
        let ints = |at: Option<(usize, usize)>, what| -> Result<Option<[f64; 3]>> {
            numbers::<3>(&words, at, what, line_no)
        };
        let image = ints(image, "image")?.unwrap_or([0.0; 3]);
        if image
            .iter()
            .any(|c| c.fract() != 0.0 || c.abs() > f64::from(i32::MAX))
        {
            return invalid!("line {line_no}: image flags {image:?} are not integers");
        }
        rows.push(Row {
            type_name,
            radius: numbers::<1>(&words, radius, "radius", line_no)?.expect("checked")[0],
            mass: numbers::<1>(&words, mass, "mass", line_no)?.map(|m| m[0]),
            position: ints(pos, "pos")?.expect("checked"),
            velocity: ints(vel, "velo")?.unwrap_or([0.0; 3]),
            angular_velocity: ints(omega, "omega")?.unwrap_or([0.0; 3]),
            image: image.map(|c| c as i32),
        });
        if let Some((s, _)) = id {
            match words[s].parse::<usize>() {
                Ok(v) => ids.push(v),
                Err(_) => return invalid!("line {line_no}: id '{}' is not a number", words[s]),
            }
        }
    }
    // Rows in the order of their ids, if the file numbers them 0..n (as this project's).
    if id.is_some() {
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        if sorted.iter().enumerate().all(|(k, &v)| k == v) {
            let mut by_id = rows.clone();
            for (row, &v) in rows.into_iter().zip(&ids) {
                by_id[v] = row;
            }
            rows = by_id;
        }
    }
    let sim_box = match get("Lattice") {
        None => None,
        Some(lattice) => {
            let m: Vec<f64> = lattice
                .split_whitespace()
                .map(str::parse)
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| {
                    crate::SystemError::Invalid(format!("Lattice=\"{lattice}\" is not 9 numbers"))
                })?;
            if m.len() != 9 {
                return invalid!("Lattice=\"{lattice}\" is not 9 numbers");
            }
            if [1, 2, 3, 5, 6, 7].iter().any(|&k| m[k] != 0.0) {
                return invalid!(
                    "Lattice=\"{lattice}\" is not orthogonal; only orthogonal boxes are \
                     simulated here"
                );
            }
            let origin = match get("Origin") {
                Some(o) => {
                    let v: Vec<f64> = o
                        .split_whitespace()
                        .filter_map(|w| w.parse().ok())
                        .collect();
                    if v.len() != 3 {
                        return invalid!("Origin=\"{o}\" is not 3 numbers");
                    }
                    [v[0], v[1], v[2]]
                }
                None => [0.0; 3],
            };
            let periodic = match get("pbc") {
                Some(p) => {
                    let v: Vec<bool> = p
                        .split_whitespace()
                        .map(|w| matches!(w, "T" | "t" | "True" | "true" | "1"))
                        .collect();
                    if v.len() != 3 {
                        return invalid!("pbc=\"{p}\" is not 3 flags");
                    }
                    [v[0], v[1], v[2]]
                }
                None => [true; 3],
            };
            if periodic == [false; 3] {
                // This project writes a free-space state with its bounding box.
                None
            } else {
                Some(file_box(origin, [m[0], m[4], m[8]], periodic)?)
            }
        }
    };
    Ok(FileState { rows, sim_box })
}

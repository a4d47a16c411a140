//! Numbers and short readings for people.

use crate::classes::Interval;

/// A number for people: at most four significant digits, trailing zeros dropped (`0.85`,
/// `1.4`, `0.0794`, `1235`); very small or large values in scientific notation.
pub fn f(v: f64) -> String {
    if v.is_nan() {
        return "–".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "∞".into() } else { "-∞".into() };
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-4..1e6).contains(&a) {
        let s = format!("{v:.3e}");
        return s;
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 9) as usize;
    geardyn_io::figure::fixed(v, decimals)
}

/// A percentage (`49 %`).
pub fn pct(v: f64) -> String {
    // a share that exists but rounds to zero must not read as absent
    if v > 0.0 && v < 0.005 {
        if v < 0.001 {
            "< 0.1 %".into()
        } else {
            format!("{:.1} %", 100.0 * v)
        }
    } else {
        format!("{:.0} %", 100.0 * v)
    }
}

/// A range `a–b` (or the single value).
pub fn range(a: f64, b: f64) -> String {
    if a == b {
        f(a)
    } else {
        format!("{}–{}", f(a), f(b))
    }
}

/// The ranges `r` (from [`crate::classes::ranges`]) for people: `0.1–0.2, 0.5`, or `none`.
pub fn ranges_text(r: &[(f64, f64, usize)]) -> String {
    if r.is_empty() {
        "none".into()
    } else {
        r.iter()
            .map(|c| range(c.0, c.1))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `name = value` pairs for people: `omega = 1.4, F = 0.07`.
pub fn sets(sets: &[(&str, f64)]) -> String {
    sets.iter()
        .map(|(k, v)| format!("{k} = {}", f(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Rows of an interval table: `from, to, motion, back-side contact, values`.
pub fn interval_rows(iv: &[Interval]) -> Vec<Vec<String>> {
    iv.iter()
        .map(|i| {
            vec![
                f(i.from),
                f(i.to),
                i.name.clone(),
                i.mesh_period.map_or(String::new(), |m| m.to_string()),
                (if i.back { "yes" } else { "no" }).into(),
                i.count.to_string(),
            ]
        })
        .collect()
}

/// Header of [`interval_rows`].
pub fn interval_header(param: &str) -> Vec<String> {
    vec![
        format!("{param} from"),
        format!("{param} to"),
        "motion".into(),
        "mesh period".into(),
        "back-side contact".into(),
        "values".into(),
    ]
}

/// A compact sequence of interval names: `1-0-0-1-0 → 2-1-0-1-0 → chaotic → ...` (runs of
/// fewer than `min` values are left out, repeated names merged).
pub fn sequence(iv: &[Interval], min: usize) -> String {
    let mut out: Vec<String> = Vec::new();
    for i in iv.iter().filter(|i| i.count >= min) {
        let d = i.display();
        if out.last() != Some(&d) {
            out.push(d);
        }
    }
    out.join(" → ")
}

/// Adds to the evidence of every claim about chaos the values of `pts` that are transient chaos
/// ([`transient_note`]), as many of them as the evidence has room for.
pub fn note_transients(
    claims: &mut [crate::claims::Claim],
    pts: &[crate::classes::Pt],
    param: &str,
    unit: &str,
) {
    for c in claims {
        if !c.claim.to_lowercase().contains("chao") {
            continue;
        }
        let room = crate::claims::EVIDENCE_MAX.saturating_sub(c.evidence.chars().count() + 1);
        let note = (0..=3)
            .rev()
            .filter_map(|n| transient_note(pts, param, unit, n))
            .find(|n| n.chars().count() <= room);
        if let Some(note) = note {
            c.evidence = format!("{} {note}", c.evidence);
        }
    }
}

/// What a claim about chaos adds when some of the values it reads are transient chaos: where
/// (with `param` = value; the first `items` of them named with their mean lifetime in `unit` and
/// the orbit the motion settles on), `None` when no value is. An integration of a few hundred
/// periods sees such a value as chaos: that explains a seed's "chaos" there rather than
/// contradicting it.
pub fn transient_note(
    pts: &[crate::classes::Pt],
    param: &str,
    unit: &str,
    items: usize,
) -> Option<String> {
    let tr: Vec<&crate::classes::Pt> = pts.iter().filter(|p| p.lifetime.is_some()).collect();
    if tr.is_empty() {
        return None;
    }
    let named: Vec<String> = tr
        .iter()
        .take(items)
        .map(|p| {
            let (l, se) = p.lifetime.expect("filtered");
            format!(
                "{param} = {} ({} ± {} {unit}, then {})",
                f(p.value),
                f(l.round()),
                f(se.round()),
                p.name
            )
        })
        .collect();
    let rest = tr.len() - named.len();
    let list = match (named.is_empty(), rest) {
        (true, _) => format!("{rest} values"),
        (false, 0) => named.join(", "),
        (false, _) => format!("{} and {rest} more", named.join(", ")),
    };
    Some(format!(
        "Transient chaos (escape test; mean lifetime, then the orbit) at {list}: chaos to a short integration."
    ))
}

/// The values whose verdict the twin sweep does not confirm ([`crate::classes::fragile`]), in
/// words, of `n` values of `param`.
pub fn fragile_reading(fragile: &[f64], n: usize, param: &str) -> String {
    if fragile.is_empty() {
        return format!(
            "Every one of the {n} verdicts is the same with the other integrator and twice the transient."
        );
    }
    let list: Vec<String> = fragile.iter().map(|&x| f(x)).collect();
    format!(
        "{} of {n} verdicts change with the other integrator and twice the transient (next to a crisis or a bifurcation), at {param} = {}: they are flagged, not counted as decided, in the claims.",
        fragile.len(),
        list.join(", ")
    )
}

/// Adds to the evidence of `claims` the values of `param` not counted as decided (`fragile`), where
/// the evidence has room.
pub fn note_fragile(claims: &mut [crate::claims::Claim], fragile: &[f64], param: &str) {
    if fragile.is_empty() {
        return;
    }
    let list: Vec<String> = fragile.iter().map(|&x| f(x)).collect();
    let note = format!(
        "Not counted: {param} = {} (the verdict changes with the integrator and a doubled transient).",
        list.join(", ")
    );
    for c in claims {
        if c.evidence.chars().count() + 1 + note.chars().count() <= crate::claims::EVIDENCE_MAX {
            c.evidence = format!("{} {note}", c.evidence);
        }
    }
}

#[cfg(test)]
mod tests {
    /// A periodic value (`lifetime` given: transient chaos first) or a chaotic one.
    fn run_at(value: f64, name: &str, lifetime: Option<(f64, f64)>) -> crate::classes::Pt {
        crate::classes::Pt {
            lifetime,
            ..crate::classes::Pt::named(value, name)
        }
    }

    #[test]
    fn transient_chaos_is_named_with_its_lifetime_and_orbit() {
        let pts = [
            run_at(1.7, "chaotic", None),
            run_at(1.725, "1-20-0", Some((6783.2, 2261.1))),
        ];
        let note = transient_note(&pts, "omega", "revolutions", 3).unwrap();
        assert!(
            note.contains("omega = 1.725 (6783 ± 2261 revolutions, then 1-20-0)"),
            "{note}"
        );
        assert!(transient_note(&pts[..1], "omega", "revolutions", 3).is_none());
        assert!(transient_note(&pts, "omega", "revolutions", 0)
            .unwrap()
            .contains("at 1 values"));
    }

    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(f(0.85), "0.85");
        assert_eq!(f(1.4000001933), "1.4");
        assert_eq!(f(0.07939), "0.07939");
        assert_eq!(f(1.0), "1");
        assert_eq!(f(1234.567), "1235");
        assert_eq!(f(-0.00001), "-1.000e-5");
        assert_eq!(range(0.1, 0.1), "0.1");
    }

    #[test]
    fn small_shares_do_not_read_as_absent() {
        for (share, text) in [
            (0.0, "0 %"),
            (0.0004, "< 0.1 %"),
            (0.003, "0.3 %"),
            (0.5, "50 %"),
        ] {
            assert_eq!(pct(share), text);
        }
    }
}

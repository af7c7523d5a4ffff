//! The parents-file parser on arbitrary text, with vertex counts from the first bytes: every
//! pair it accepts must be in range and each new vertex must appear once.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use topoccd::io::sequence::parse_parents;

fuzz_target!(|data: &[u8]| {
    let [a, b, rest @ ..] = data else { return };
    let previous = usize::from(*a);
    let current = previous + usize::from(*b);
    let text = String::from_utf8_lossy(rest);
    if let Ok(pairs) = parse_parents(&text, Path::new("fuzz.parents"), previous, current) {
        let mut seen = vec![false; current - previous];
        for (new, parent) in pairs {
            let (new, parent) = (new as usize, parent as usize);
            assert!(previous <= new && new < current && parent < previous);
            assert!(!std::mem::replace(&mut seen[new - previous], true));
        }
    }
});

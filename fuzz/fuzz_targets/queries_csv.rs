//! The query CSV parser on arbitrary text: whole 8-row queries of finite points, or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use topoccd::io::queries::parse_queries;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(queries) = parse_queries(&text, Path::new("fuzz.csv")) {
        for q in queries {
            assert!(q.points.iter().all(|p| p.is_finite()));
            assert!(q.line >= 1);
        }
    }
});

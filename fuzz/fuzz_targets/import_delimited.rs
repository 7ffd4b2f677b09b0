//! `sinsbench import` of arbitrary bytes as delimited text: the first byte picks comma with a
//! header and `#` comments, whitespace without a header, or tabs with recorded stamps, a
//! counter and split gaps; the rest is the recording (gzip and zip magic included, so the
//! decompressors are fuzzed too).
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, import_bytes};

const SITE: &str = "[site]\nlatitude_deg = 34.2\nlongitude_deg = 108.9\nheight_m = 380\n";

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let Some((&pick, rest)) = data.split_first() else {
            return;
        };
        let desc = match pick % 3 {
            0 => "format = \"delimited\"\n[delimited]\ncomment = \"#\"\n[time]\ncolumn = \"t\"\n\
                  [gyro]\ncolumns = [\"gx\", \"gy\", \"gz\"]\nquantity = \"rate\"\nunit = \"deg/s\"\n\
                  [accel]\ncolumns = [\"ax\", \"ay\", \"az\"]\nquantity = \"rate\"\nunit = \"g\"\n"
                .to_string(),
            1 => "format = \"delimited\"\n[delimited]\ndelimiter = \"whitespace\"\nheader = false\n\
                  [time]\nrate_hz = 100\n[gyro]\ncolumns = [0, 1, 2]\nquantity = \"increment\"\n\
                  unit = \"arcsec\"\n[accel]\ncolumns = [3, 4, 5]\nquantity = \"increment\"\nunit = \"ug*s\"\n\
                  [axes]\nconvention = \"frd\"\n"
                .to_string(),
            _ => "format = \"delimited\"\n[delimited]\ndelimiter = \"tab\"\n[time]\ncolumn = 0\n\
                  counter = 1\nunit = \"ms\"\nstamps = \"recorded\"\non_gap = \"split\"\nrate_hz = 50\n\
                  [gyro]\ncolumns = [2, 3, 4]\nquantity = \"rate\"\nunit = \"rad/s\"\nrule = \"hold\"\n\
                  [accel]\ncolumns = [5, 6, 7]\nquantity = \"rate\"\nunit = \"m/s^2\"\n\
                  [temperature]\ncolumns = [8]\nunit = \"K\"\n"
                .to_string(),
        };
        import_bytes("recording.txt", rest, &format!("{desc}{SITE}"));
    })
});

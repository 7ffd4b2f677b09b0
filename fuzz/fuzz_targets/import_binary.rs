//! `sinsbench import` of arbitrary bytes as fixed binary records: the first byte picks the byte
//! order and whether the time is a stamp or a counter; the rest is the file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, import_bytes};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let Some((&pick, rest)) = data.split_first() else {
            return;
        };
        let order = if pick & 1 == 0 { "little" } else { "big" };
        let time = if pick & 2 == 0 {
            "column = \"t\"\nunit = \"us\""
        } else {
            "counter = \"n\"\ncounter_modulo = 65536\nrate_hz = 200"
        };
        let desc = format!(
            "format = \"binary\"\n[binary]\nheader_bytes = 3\nbyte_order = \"{order}\"\nfields = [\n\
             {{ name = \"t\", type = \"f64\" }}, {{ name = \"n\", type = \"u16\" }},\n\
             {{ name = \"gx\", type = \"i32\" }}, {{ name = \"gy\", type = \"i32\" }}, {{ name = \"gz\", type = \"i32\" }},\n\
             {{ name = \"ax\", type = \"f32\" }}, {{ name = \"ay\", type = \"f32\" }}, {{ name = \"az\", type = \"f32\" }},\n\
             {{ name = \"p\", type = \"pad1\" }}, {{ name = \"tc\", type = \"i16\" }} ]\n\
             [time]\n{time}\n[gyro]\ncolumns = [\"gx\", \"gy\", \"gz\"]\nquantity = \"increment\"\n\
             unit = \"counts\"\ncount_scale = [0.1, 0.1, 0.1]\ncount_unit = \"arcsec\"\n\
             [accel]\ncolumns = [\"ax\", \"ay\", \"az\"]\nquantity = \"rate\"\nunit = \"mg\"\n\
             [temperature]\ncolumns = [\"tc\"]\n\
             [site]\nlatitude_deg = 34.2\nlongitude_deg = 108.9\nheight_m = 380\n"
        );
        import_bytes("recording.bin", rest, &desc);
    })
});

//! The USD layer readers (usda text, usdc and usdz by magic bytes) on any
//! bytes, through the same entry the loader uses (nesting limit, big-stack
//! parser thread): a layer or a typed error, never a panic or an abort.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    shapewright_usd::limits::with_parser_stack(|| {
        let _ = shapewright_usd::read_layer(data);
    });
});

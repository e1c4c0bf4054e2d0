//! What every chart shares: the series colours and the result of drawing.

use plotters::style::RGBColor;
use std::error::Error;

/// Series colours: blue, red, purple, green, orange (none close to the text's black).
pub(crate) const PALETTE: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
];

/// What a drawing function returns: a backend's error, boxed.
pub(crate) type DrawResult = Result<(), Box<dyn Error>>;

//! Spectra and colour (`spar::spectrum`) and the media catalogue
//! (`spar::material`). One test binary; each file is a module.

mod material_biaxial_gems;
mod material_gems;
mod material_indices;
mod material_parse;
mod spectrum_colour;
mod spectrum_rgb_round_trip;

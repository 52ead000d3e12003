//! Integration tests of emdstar-contact against independent references: the paper's
//! printed constants, analytic dashpot formulas, and round trips of the coordinates.

mod central_dashpot;
mod paper_constants;
mod rect_coordinates;

//! The pictures vk-render makes and writes: the output transform and its files ([`output`]), text in
//! pictures ([`text`]), contact sheets ([`sheet`]), the analysis's charts ([`chart`]), comparison reports
//! ([`report`]) and the comparison of two images the tests and reports read ([`compare`]).

pub mod chart;
pub mod compare;
pub mod output;
pub mod report;
pub mod sheet;
pub mod text;

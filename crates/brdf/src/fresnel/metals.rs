//! Mitsuba 3's other named conductors (`material="Cr"`, `"W"`, …): RGB η and k reduced from
//! the spectral optical constants it ships (`data/ior/<name>.{eta,k}.spd`, from luxpop.com and
//! Palik's handbook) by `radiometry::cie`'s rule without the illuminant (the reduction of
//! `fresnel/spectral.rs`); the reduction gives Mitsuba 3.9.1's own RGB values for all of them
//! to 1e-7 relative. `_palik` names are Mitsuba's aliases for the same data.

use super::Metal;
use radiometry::Rgb;

/// Every `material` choice: `custom`, `none`, then the named conductors.
#[rustfmt::skip]
pub const MATERIALS: &[&str] = &[
    "custom", "none", "Au", "Ag", "Cu", "Al", "AlAs", "AlAs_palik", "AlSb", "AlSb_palik", "Be", "Be_palik", "Cr",
    "CsI", "CsI_palik", "Cu2O", "Cu2O_palik", "CuO", "CuO_palik", "Cu_palik", "Hg", "HgTe", "HgTe_palik",
    "Hg_palik", "Ir", "Ir_palik", "K", "K_palik", "Li", "Li_palik", "MgO", "MgO_palik", "Mo", "Mo_palik",
    "Na_palik", "Nb", "Nb_palik", "Ni_palik", "Rh", "Rh_palik", "Se", "Se-e", "Se-e_palik", "Se_palik", "SiC",
    "SiC_palik", "SnTe", "SnTe_palik", "Ta", "Ta_palik", "Te", "Te-e", "Te-e_palik", "Te_palik", "ThF4",
    "ThF4_palik", "TiC", "TiC_palik", "TiN", "TiN_palik", "TiO2", "TiO2-e", "TiO2-e_palik", "TiO2_palik", "VC",
    "VC_palik", "VN", "VN_palik", "V_palik", "W", "a-C", "d-C", "d-C_palik",
];

/// The named conductors besides Au, Ag, Cu and Al.
#[rustfmt::skip]
#[allow(clippy::excessive_precision)]
pub const MORE_METALS: &[Metal] = &[
    Metal { name: "AlAs", eta: Rgb::new(3.605296, 3.232938, 2.216318), k: Rgb::new(0.0006794374, 0.0, 0.007512709) },
    Metal { name: "AlAs_palik", eta: Rgb::new(3.605296, 3.232938, 2.216318), k: Rgb::new(0.0006794374, 0.0, 0.007512709) },
    Metal { name: "AlSb", eta: Rgb::new(0.0, 4.139375, 4.669254), k: Rgb::new(0.0, 0.09400907, 1.30057) },
    Metal { name: "AlSb_palik", eta: Rgb::new(0.0, 4.139375, 4.669254), k: Rgb::new(0.0, 0.09400907, 1.30057) },
    Metal { name: "Be", eta: Rgb::new(4.185012, 3.185029, 2.784061), k: Rgb::new(3.835466, 3.010122, 2.868994) },
    Metal { name: "Be_palik", eta: Rgb::new(4.185012, 3.185029, 2.784061), k: Rgb::new(3.835466, 3.010122, 2.868994) },
    Metal { name: "Cr", eta: Rgb::new(4.369668, 2.916505, 1.654905), k: Rgb::new(5.206547, 4.231306, 3.754699) },
    Metal { name: "CsI", eta: Rgb::new(2.1449, 1.702319, 1.662427), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "CsI_palik", eta: Rgb::new(2.1449, 1.702319, 1.662427), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "Cu2O", eta: Rgb::new(3.551773, 2.94987, 2.751875), k: Rgb::new(0.114207, 0.1938969, 0.6061339) },
    Metal { name: "Cu2O_palik", eta: Rgb::new(3.551773, 2.94987, 2.751875), k: Rgb::new(0.114207, 0.1938969, 0.6061339) },
    Metal { name: "CuO", eta: Rgb::new(3.247541, 2.447805, 2.21022), k: Rgb::new(0.5210896, 0.5700307, 0.7221789) },
    Metal { name: "CuO_palik", eta: Rgb::new(3.247541, 2.447805, 2.21022), k: Rgb::new(0.5210896, 0.5700307, 0.7221789) },
    Metal { name: "Cu_palik", eta: Rgb::new(0.2132285, 0.9197154, 1.102411), k: Rgb::new(3.921873, 2.457332, 2.136584) },
    Metal { name: "Hg", eta: Rgb::new(2.398939, 1.440028, 0.9095704), k: Rgb::new(6.327587, 4.371925, 3.421763) },
    Metal { name: "HgTe", eta: Rgb::new(4.77904, 3.231196, 2.659901), k: Rgb::new(1.631613, 1.58081, 1.729287) },
    Metal { name: "HgTe_palik", eta: Rgb::new(4.77904, 3.231196, 2.659901), k: Rgb::new(1.631613, 1.58081, 1.729287) },
    Metal { name: "Hg_palik", eta: Rgb::new(2.398939, 1.440028, 0.9095704), k: Rgb::new(6.327587, 4.371925, 3.421763) },
    Metal { name: "Ir", eta: Rgb::new(3.0863, 2.08219, 1.617914), k: Rgb::new(5.592153, 4.067088, 3.267312) },
    Metal { name: "Ir_palik", eta: Rgb::new(3.0863, 2.08219, 1.617914), k: Rgb::new(5.592153, 4.067088, 3.267312) },
    Metal { name: "K", eta: Rgb::new(0.06404319, 0.04640977, 0.03818491), k: Rgb::new(2.1042, 1.34894, 0.9131258) },
    Metal { name: "K_palik", eta: Rgb::new(0.06404319, 0.04640977, 0.03818491), k: Rgb::new(2.1042, 1.34894, 0.9131258) },
    Metal { name: "Li", eta: Rgb::new(0.2657909, 0.1956183, 0.2209486), k: Rgb::new(3.540155, 2.311123, 1.668607) },
    Metal { name: "Li_palik", eta: Rgb::new(0.2657909, 0.1956183, 0.2209486), k: Rgb::new(3.540155, 2.311123, 1.668607) },
    Metal { name: "MgO", eta: Rgb::new(2.089584, 1.650723, 1.594879), k: Rgb::new(4.332695e-12, 0.0, 2.498646e-11) },
    Metal { name: "MgO_palik", eta: Rgb::new(2.089584, 1.650723, 1.594879), k: Rgb::new(4.332695e-12, 0.0, 2.498646e-11) },
    Metal { name: "Mo", eta: Rgb::new(4.483974, 3.525131, 2.77631), k: Rgb::new(4.111438, 3.420827, 3.150607) },
    Metal { name: "Mo_palik", eta: Rgb::new(4.483974, 3.525131, 2.77631), k: Rgb::new(4.111438, 3.420827, 3.150607) },
    Metal { name: "Na_palik", eta: Rgb::new(0.06026936, 0.05614095, 0.06198843), k: Rgb::new(3.179273, 2.112491, 1.579041) },
    Metal { name: "Nb", eta: Rgb::new(3.420074, 2.790093, 2.395629), k: Rgb::new(3.441395, 2.737666, 2.579746) },
    Metal { name: "Nb_palik", eta: Rgb::new(3.420074, 2.790093, 2.395629), k: Rgb::new(3.441395, 2.737666, 2.579746) },
    Metal { name: "Ni_palik", eta: Rgb::new(2.367305, 1.663373, 1.467078), k: Rgb::new(4.498812, 3.050153, 2.345439) },
    Metal { name: "Rh", eta: Rgb::new(2.585793, 1.860216, 1.554263), k: Rgb::new(6.78226, 4.702987, 3.976073) },
    Metal { name: "Rh_palik", eta: Rgb::new(2.585793, 1.860216, 1.554263), k: Rgb::new(6.78226, 4.702987, 3.976073) },
    Metal { name: "Se", eta: Rgb::new(4.058312, 2.842935, 2.820853), k: Rgb::new(0.7540496, 0.6384435, 0.5218075) },
    Metal { name: "Se-e", eta: Rgb::new(5.722849, 4.165736, 4.081338), k: Rgb::new(0.8711364, 1.105157, 1.56532) },
    Metal { name: "Se-e_palik", eta: Rgb::new(5.722849, 4.165736, 4.081338), k: Rgb::new(0.8711364, 1.105157, 1.56532) },
    Metal { name: "Se_palik", eta: Rgb::new(4.058312, 2.842935, 2.820853), k: Rgb::new(0.7540496, 0.6384435, 0.5218075) },
    Metal { name: "SiC", eta: Rgb::new(3.172342, 2.525972, 2.47937), k: Rgb::new(7.537664e-07, 0.0, 1.019253e-05) },
    Metal { name: "SiC_palik", eta: Rgb::new(3.172342, 2.525972, 2.47937), k: Rgb::new(7.537664e-07, 0.0, 1.019253e-05) },
    Metal { name: "SnTe", eta: Rgb::new(4.52425, 1.981645, 1.281591), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "SnTe_palik", eta: Rgb::new(4.52425, 1.981645, 1.281591), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "Ta", eta: Rgb::new(2.062721, 2.392939, 2.627929), k: Rgb::new(2.40836, 1.741486, 1.947028) },
    Metal { name: "Ta_palik", eta: Rgb::new(2.062721, 2.392939, 2.627929), k: Rgb::new(2.40836, 1.741486, 1.947028) },
    Metal { name: "Te", eta: Rgb::new(7.390234, 4.482105, 2.637106), k: Rgb::new(3.256022, 3.527059, 3.292054) },
    Metal { name: "Te-e", eta: Rgb::new(7.508907, 4.296429, 2.369988), k: Rgb::new(5.583929, 4.947205, 3.997592) },
    Metal { name: "Te-e_palik", eta: Rgb::new(7.508907, 4.296429, 2.369988), k: Rgb::new(5.583929, 4.947205, 3.997592) },
    Metal { name: "Te_palik", eta: Rgb::new(7.390234, 4.482105, 2.637106), k: Rgb::new(3.256022, 3.527059, 3.292054) },
    Metal { name: "ThF4", eta: Rgb::new(1.830714, 1.442229, 1.387648), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "ThF4_palik", eta: Rgb::new(1.830714, 1.442229, 1.387648), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "TiC", eta: Rgb::new(3.700528, 2.837422, 2.582287), k: Rgb::new(3.265635, 2.351589, 2.17279) },
    Metal { name: "TiC_palik", eta: Rgb::new(3.700528, 2.837422, 2.582287), k: Rgb::new(3.265635, 2.351589, 2.17279) },
    Metal { name: "TiN", eta: Rgb::new(1.64845, 1.150516, 1.379823), k: Rgb::new(3.368328, 1.943498, 1.102068) },
    Metal { name: "TiN_palik", eta: Rgb::new(1.64845, 1.150516, 1.379823), k: Rgb::new(3.368328, 1.943498, 1.102068) },
    Metal { name: "TiO2", eta: Rgb::new(3.45661, 2.801736, 2.905175), k: Rgb::new(0.0001052648, 0.0, 0.0006528865) },
    Metal { name: "TiO2-e", eta: Rgb::new(3.106565, 2.513168, 2.582444), k: Rgb::new(2.975161e-05, 0.0, 0.0001826981) },
    Metal { name: "TiO2-e_palik", eta: Rgb::new(3.106565, 2.513168, 2.582444), k: Rgb::new(2.975161e-05, 0.0, 0.0001826981) },
    Metal { name: "TiO2_palik", eta: Rgb::new(3.45661, 2.801736, 2.905175), k: Rgb::new(0.0001052648, 0.0, 0.0006528865) },
    Metal { name: "VC", eta: Rgb::new(3.657566, 2.752736, 2.532672), k: Rgb::new(3.068301, 2.198687, 1.963193) },
    Metal { name: "VC_palik", eta: Rgb::new(3.657566, 2.752736, 2.532672), k: Rgb::new(3.068301, 2.198687, 1.963193) },
    Metal { name: "VN", eta: Rgb::new(2.865602, 2.119189, 1.940091), k: Rgb::new(3.032243, 2.056116, 1.616306) },
    Metal { name: "VN_palik", eta: Rgb::new(2.865602, 2.119189, 1.940091), k: Rgb::new(3.032243, 2.056116, 1.616306) },
    Metal { name: "V_palik", eta: Rgb::new(4.277582, 3.512949, 2.761071), k: Rgb::new(3.491301, 2.889455, 3.111522) },
    Metal { name: "W", eta: Rgb::new(4.370817, 3.300247, 2.998407), k: Rgb::new(3.500641, 2.604874, 2.273233) },
    Metal { name: "a-C", eta: Rgb::new(2.944046, 2.227136, 1.968162), k: Rgb::new(0.8874649, 0.7992985, 0.8152899) },
    Metal { name: "d-C", eta: Rgb::new(2.70872, 2.318826, 2.228897), k: Rgb::new(0.0, 0.0, 0.0) },
    Metal { name: "d-C_palik", eta: Rgb::new(2.70872, 2.318826, 2.228897), k: Rgb::new(0.0, 0.0, 0.0) },
];

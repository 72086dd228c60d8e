pub mod lander_edl;
pub mod plants;
pub mod random_ocsp;
pub mod random_plant;

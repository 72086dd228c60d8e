pub mod plants;
pub mod random_ocsp;

pub mod random_ocsp;

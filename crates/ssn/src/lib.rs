pub mod siconos;

//! eMD* collision rule (being implemented).

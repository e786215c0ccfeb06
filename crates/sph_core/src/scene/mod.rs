//! Scenes as data: the RON scene file, its checks and what it builds ([`file`]), its named
//! controls ([`controls`]), and the mutations the fuzz test loads ([`mutations`]).

pub mod controls;
pub mod file;
pub mod mutations;

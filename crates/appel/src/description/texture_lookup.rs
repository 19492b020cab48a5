//! How an image texture is looked up: its filter and what happens outside [0, 1]. Shared by the
//! mesh readers (a file's material states them) and the bitmap texture that applies them.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    #[default]
    Bilinear,
    Nearest,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    #[default]
    Repeat,
    Mirror,
    Clamp,
}

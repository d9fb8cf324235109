//! C ABI of the OpenImageIO shim (`shim/oiio_shim.h`). (work in progress)

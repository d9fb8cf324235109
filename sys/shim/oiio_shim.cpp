// spar's OpenImageIO shim (work in progress).
#include "oiio_shim.h"
#include <OpenImageIO/imageio.h>

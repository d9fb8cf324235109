/* The one header bindgen reads. */
#include <embree3/rtcore.h>

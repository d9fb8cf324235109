/* C ABI of spar's OpenImageIO shim (work in progress). */
#pragma once

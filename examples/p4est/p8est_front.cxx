// The 3D build of p4est_front.cxx: p4est's own idiom (p4est_to_p8est.h).
#define P4_TO_P8
#include "p4est_front.cxx"

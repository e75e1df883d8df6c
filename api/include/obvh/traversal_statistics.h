/* obvh extension, not part of Embree: counts of the bounding-volume tests and leaf visits of the
   calling thread's single-ray queries (rtcIntersect1, rtcOccluded1), for heatmaps. Exported by
   libobvh.so and obvh's libembree3.so.3; a program can look the functions up with dlsym to find
   out whether it runs on obvh. Counting is off until a thread enables it. */
#ifndef OBVH_TRAVERSAL_STATISTICS_H
#define OBVH_TRAVERSAL_STATISTICS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ObvhTraversalStatistics {
  uint64_t boundingVolumeTests; /* child boxes (axis-aligned or oriented) tested against a ray */
  uint64_t leafVisits;          /* leaves whose primitives were tested */
} ObvhTraversalStatistics;

/* Starts (enable != 0) or stops counting the calling thread's queries; starting resets the counts. */
void obvhEnableTraversalStatistics(int enable);

/* Copies the calling thread's counts since the last call (or since enabling) and resets them. */
void obvhTakeTraversalStatistics(ObvhTraversalStatistics* statistics);

#ifdef __cplusplus
}
#endif

#endif

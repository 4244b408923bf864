// penetration.hpp: penetration depth on the overlapping cases (alpha_ref < 1 - 1e-6):
// dcol_signed_distance against Coal's EPA (coal::distance, default request), FCL 0.7's signed
// distance (GST_LIBCCD: GJK + libccd's EPA; GST_INDEP: FCL's own GJK, then collide's EPA),
// libccd's ccdMPRPenetration, and an independent depth (depth_check.hpp). Untimed; the timing of
// dcol_signed_distance against coal::distance on the same cases is in the main table's samples.
#ifndef DCOL_BENCH_PENETRATION_HPP
#define DCOL_BENCH_PENETRATION_HPP

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compare_common.h"
#include "depth_check.hpp"

// The peers, in table order.
enum DepthPeerId { kPeerCoal = 0, kPeerFclCcd, kPeerFclIndep, kPeerMpr, kPeerCount };

// One overlapping case's depths (> 0 penetrating) from the peers; NaN: not run (no Coal, not an
// FCL pair) or threw. `raw`: the value as the library returned it (signed distance, or the MPR
// depth), for the "what FCL returns" counts.
struct PeerDepths {
  double depth[kPeerCount] = {NAN, NAN, NAN, NAN};
  double raw[kPeerCount] = {NAN, NAN, NAN, NAN};
  Dir normal[kPeerCount] = {};  // candidate directions for the independent search (0: none)
};

struct DepthPeerStats {
  long checked = 0, agree = 0;
  long no_depth = 0;       // returned a non-negative distance, or exactly -1 (FCL: EPA failed)
  long dcol_closer = 0, peer_closer = 0;  // disagreements: closer to the independent depth
  long peer_deeper = 0;    // disagreements where the peer is deeper than the independent depth
                           // (an upper bound) by more than its tolerance: wrong for certain
  double max_diff = 0;     // max |depth - dcol depth| over the checked cases
  double max_ind = 0;      // max |depth - independent depth|
  double max_short = 0;    // max (independent depth - depth): how much shallower at most
  std::string worst = "";  // the case of max_diff
};

struct DepthRow {
  long cases = 0;        // overlapping cases (alpha_ref < 1 - 1e-6)
  long dcol_failed = 0;  // dcol_signed_distance returned an error (left out)
  DepthPeerStats peer[kPeerCount];
  // dcol against the independent depth
  long ind_checked = 0, ind_within9 = 0, ind_within6 = 0;
  long dcol_deeper = 0;     // dcol's depth above the independent one (an upper bound) by > 1e-9
  long sampling_missed = 0; // the Fibonacci seeds alone stayed > 1e-9 above the final minimum
  double sampling_gap_max = 0;  // the largest such gap
  double ind_max = 0;
  std::string ind_worst = "";
  double own_normal_max = 0;  // max |f(dcol's normal) - dcol's depth|: dcol's normal checked
  long evaluations = 0;
};

/// Agreement tolerances (absolute, times max(1, depth)) of each peer with dcol.
double depth_tolerance(int peer, double dcol_tol);

/// Records one overlapping case: dcol's signed distance result (status ok), the peers' depths;
/// runs the independent check. `where` names the case for the worst-case strings.
void record_depth(DepthRow& row, const cmp_case& c, bool dcol_ok,
                  const dcol_signed_distance_result& sd, const PeerDepths& peers,
                  double dcol_tol, const std::string& where);

/// Writes the section "Penetration depth" of benchmark.md and a summary on stdout.
/// `timing`: the lines of the signed-distance timing table (already formatted, may be empty).
void write_depth_section(FILE* md, const std::vector<DepthRow>& rows,
                         const std::vector<std::string>& pair_names, bool have_coal,
                         double dcol_tol, const std::string& timing);

#endif  // DCOL_BENCH_PENETRATION_HPP

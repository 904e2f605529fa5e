#pragma once
/// \file
/// Multiway registration of a sequence of scans (docs/reconstruction.md):
/// every scan paired with its best-overlapping partners (and its
/// neighbours in the sequence, and the last with the first), each pair
/// registered by 3D-NDT on coarse cells and finished by point-to-plane ICP
/// at the sensor's noise scale, the pairs made the edges of a pose graph
/// with the robot's reported poses as priors and its relative motions as
/// odometry (solved with CHOLMOD, pose_graph.hpp), the robot's precision
/// measured on the data (variance components, pose_graph_variance.hpp),
/// then pairs chosen and registered again at the graph's poses, a few
/// rounds. Optionally each scan is first registered against the model of
/// the scans before it (the paper's scan-to-model pass).
///
/// Streaming: a scan is handed over once; what is kept is the model (cube
/// centroids) and each scan reduced to 2 mm cube centroids (a few thousand
/// points), a fraction of the fused cloud.

#include <icrkit/core/point_cloud.hpp>
#include <icrkit/ndt/ndt_registration.hpp>
#include <icrkit/reconstruction/registration/joint_refinement.hpp>
#include <icrkit/reconstruction/registration/point_to_plane_icp.hpp>
#include <icrkit/reconstruction/registration/pose_graph.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <memory>
#include <string>
#include <optional>
#include <vector>

namespace icrkit::reconstruction {

struct SequenceRegistrationParameters {
  /// Scan-to-model and loop-closure NDT. The defaults (4/2/1 cm cells,
  /// sources reduced to 2 mm cube centroids) suit objects of 5-30 cm
  /// scanned at 1-3 mm spacing.
  ndt::NdtParameters ndt = [] {
    ndt::NdtParameters p;
    p.resolutions = {0.04, 0.02, 0.01, 0.005};
    p.source_voxel_size = 0.002;
    return p;
  }();
  /// NDT cells finer than this many times the first scan's median point
  /// spacing are dropped from `ndt.resolutions` (a 176 x 144 ToF camera
  /// gives 2-3 mm spacing, too sparse for 5 mm cells). 0: keep all.
  double min_resolution_spacing_factor = 3.5;
  /// Each scan is kept for the pair-wise stage as the centroids of its
  /// points in cubes of this edge (metres); <= 0: every point.
  double kept_voxel_size = 0.001;
  /// The model is kept as the centroids of the registered points in cubes
  /// of this edge (metres): its size then follows the object's surface
  /// area, not the number of scans.
  double model_voxel_size = 0.0015;
  /// The sequential pass: each scan registered (NDT) against the model of
  /// the scans before it, the starting poses of the pair-wise stage. false:
  /// the pairs start from the reported poses (their NDT stage has the same
  /// basin), in parallel. Off by default: on the real PrimeSense bunny and
  /// the simulated sets the multiway rounds end at the same poses either
  /// way, and the sequential pass is a third of the time.
  bool scan_to_model = false;
  /// Each scan starts from its reported pose corrected by the previous
  /// scan's correction (arm drift and hand-eye errors change slowly).
  bool propagate_correction = true;
  /// A registration is rejected (the scan keeps its starting pose, stays out
  /// of the model and gets a weak edge) when it moves the scan's points (at
  /// their centroid) or turns them further than these from the reported
  /// pose (metres, radians) ...
  double max_correction_translation = 0.03;
  double max_correction_rotation = 0.25;
  /// ... or ends with a normalised NDT score below this (0: no point near a
  /// Gaussian, ~1: every point on its cell's mean; partial overlap lowers it).
  double min_normalized_score = 0.15;
  /// Degeneracy: a registration's correction is kept only along the
  /// directions its NDT Hessian constrains (eigenvalue at least this
  /// fraction of the largest, rotations scaled by the points' radius); the
  /// rest comes from the reported pose. A cup or a bottle on a turntable
  /// does not show its rotation about its own axis. 0: keep everything.
  double degeneracy_ratio = 0.05;
  /// Pose graph edges of pair-wise registrations carry the NDT Hessian as
  /// their information (scaled so that the best-constrained translation has
  /// `registration_sigma_translation`): unobserved directions are then left
  /// to the priors. false: a diagonal information from the two sigmas.
  bool hessian_information = true;
  /// Pairwise refinement after the sequential pass: every pair of scans
  /// whose points share at least this fraction of 1 cm cubes (of the
  /// smaller scan, at the scan-to-model poses) is registered pair-wise, up
  /// to `max_partners` best-overlapping partners per scan; the pairs become
  /// the pose graph's edges. Sequential scan-to-model registration leaves a
  /// slow drift around a closed circle; the pairs (the last/first pair among
  /// them: the loop closure) spread it.
  double min_pair_overlap = 0.3;
  int max_partners = 4;
  /// Always register consecutive scans as pairs, whatever their overlap at
  /// the current poses (from poses a centimetre off, overlap is
  /// underestimated; a robot moves between consecutive views little).
  bool sequence_pairs = true;
  /// Always try the last scan against the first (turntable, closed circle).
  bool loop_closure = true;
  /// Standard deviations of an accepted registration's relative pose
  /// (metres, radians): the information of the pose graph's edges.
  double registration_sigma_translation = 0.0005;
  double registration_sigma_rotation = 0.002;
  /// Standard deviations of the reported poses, used as priors that place
  /// the registered model in the robot's frame (a least-squares fit to all
  /// reported poses rather than trusting the first). <= 0: no priors, the
  /// first scan is held at its reported pose instead.
  double prior_sigma_translation = 0.005;
  double prior_sigma_rotation = 0.01;
  /// Standard deviations of the robot's motion between consecutive scans
  /// (metres, radians): a robot arm or turntable repeats relative motions
  /// far better than it knows its absolute pose (hand-eye and mounting
  /// errors are constant). Edges between consecutive reported poses. <= 0:
  /// none.
  double odometry_sigma_translation = 0.0005;
  double odometry_sigma_rotation = 0.001;
  /// Fine stage of every pair: point-to-plane ICP (point_to_plane_icp.hpp)
  /// after the pair's NDT, against the target scan's `kept_voxel_size`
  /// points and their tangent planes, from the source reduced to cubes of
  /// `icp_source_voxel_size` (metres). An NDT cell of 5 mm or more models a
  /// curved surface too coarsely for the sensor's ~1 mm noise. false: NDT only.
  bool icp_refinement = true;
  PointToPlaneIcpParameters icp;
  /// The `icp` distances suit scans up to this point spacing (metres); a
  /// first scan spaced more sparsely scales them (and the kernel) by its
  /// spacing over this. <= 0: never scaled.
  double icp_spacing_reference = 0.0015;
  double icp_source_voxel_size = 0.0025;
  /// ... and at most this many of them (an even stride): precision grows
  /// with the square root of the count, the cost linearly.
  std::size_t icp_max_source_points = 1200;
  /// Last: all views refined at once against each other's face-on points
  /// (joint_refinement.hpp). Its distances, kernel and cubes are scaled
  /// with the ICP's for a sparser sensor; each view is held to the graph's
  /// pose by at most the robot's odometry sigmas (an arm's views stay put).
  /// On the real recording's views it brings the fused cloud from 0.90-1.01
  /// to 0.74-0.76 mm from the reference (medians of the 3, 5 and 8 mm
  /// classes; two 8 mm runs still fail)
  /// (docs/reconstruction.md, "The joint refinement by default"); false:
  /// the graph's poses (`icrkit reconstruct --no-joint-refinement`). It
  /// reads which points face the sensor, so each scan's points must be in
  /// its sensor's frame (the sensor at the origin), as icrkit's readers
  /// give them; scans stored otherwise (a laser scanner's object-centred
  /// frame) should turn it off.
  bool joint_refinement = true;
  /// Each view's tangent planes summed point by point in index order (one
  /// k-d tree query per point); false (default): cube by cube
  /// (RadiusCells: faster, the sums differ in their last bits; the sweep's
  /// 54 real-view runs as before to 0.002 mm).
  bool normals_in_index_order = false;
  JointRefinementParameters joint;
  /// Its poses are kept only when its face-on correspondences link at least
  /// this many pairs of views per pair the graph accepted in its last round.
  /// Fewer: the face-on surfaces are too few to hold the views, and the
  /// graph's poses stand. Measured: 0.62 on synthetic views looking down
  /// 27 deg onto a block toy (no side face is face-on; the step moved them
  /// 0.3 mm from the truth, where the graph left them at 0.05), 0.89-3.6 on
  /// the nine simulated sets, 1.0-1.6 on the real recording's 9-18 views.
  /// 0: kept whenever the graph accepted at least one pair (with none, the
  /// views hardly overlap and the graph's poses stand).
  double joint_min_linked_pair_ratio = 0.75;
  /// Window radius of the normals it matches along (metres): wider than
  /// the pairs' tangent planes, since the face-on test and the normal
  /// agreement read them too (the tangent planes instead: 0.01 mm farther
  /// from the reference on the sweep's real views).
  double joint_normal_radius = 0.0035;
  /// First round: the pairs start from the robot's poses, a centimetre or
  /// more apart. true: 3D-NDT on coarse cells brings them within the ICP's
  /// reach; false: the ICP starts with these wider pairing distances
  /// (metres) before its own.
  bool pair_ndt = true;
  /// ... also for a pair of views both placed by the model alignment's
  /// last level (1 cm cells against all the other views: within the ICP's
  /// 6 mm reach). false (default): such pairs start with the ICP. Batch
  /// registration only: as the scans arrive, the first round's pairs are
  /// registered in add(), each view aligned to the earlier ones only.
  /// With a coarser last alignment level than 1 cm, set it to true.
  bool pair_ndt_for_placed_views = false;
  /// A first-round pair of placed views that the ICP alone rejects for
  /// too little overlap (its views beyond the ICP's reach), and that would
  /// join views the accepted pairs leave apart (two groups the model
  /// alignment placed each against itself, a centimetre apart), is
  /// registered again with the coarse start (the pair's NDT, as
  /// `pair_ndt_for_placed_views`). Costs nothing where the accepted pairs
  /// link every view. Batch registration only.
  bool pair_ndt_retry_rejected = true;
  std::vector<double> icp_wide_distances{0.02, 0.01};
  /// With the ICP after it, a pair's NDT only has to reach the ICP's basin:
  /// its source is reduced to cubes of this edge (metres).
  double pair_ndt_source_voxel_size = 0.005;
  /// With the ICP after it, the NDT (scan-to-model and pairs) stops at its
  /// cells of at least this edge (metres): its finer cells cost most of its
  /// time and the ICP does their work better.
  double icp_coarsest_finish = 0.01;
  /// A pair whose ICP matches fewer than this fraction of the source's
  /// points (weighted) is rejected: the views hardly overlap.
  double min_icp_inlier_fraction = 0.15;
  /// Views against the model of the others, before the pairs: at each of
  /// these NDT cell sizes (metres, coarse to fine) every view is registered
  /// at once (each from the current poses, so the result does not depend on
  /// the order or the thread count) against the points of all the other
  /// views, and all move together. With per-view errors independent (a
  /// mobile robot: 5-8 mm and 1-2 deg per view, tens of millimetres at the
  /// object) the others' union is blurred but centred where the object is,
  /// and it covers every side a view shows, which a single partner does
  /// not; a few levels bring every view within the pairs' reach. The first
  /// level's 6 cm cells reach views 40-55 mm off at the object (a real
  /// recording at 8 mm / 2 deg per view), which 4 cm cells left where the
  /// robot put them (docs/reconstruction.md, "A 6 cm first level"). Empty:
  /// the pairs start from the reported poses.
  std::vector<double> model_alignment_resolutions{0.06, 0.04, 0.02, 0.01};
  /// A level of `model_alignment_resolutions` whose cell edge is more than
  /// this many times the object's spread is left out (the finest level is
  /// always kept; 0 keeps every level). The spread: the median over the
  /// views of each one's largest standard deviation in its own frame, so
  /// the robot's pose errors do not enlarge it. At 2, a level is left out
  /// when the object within one standard deviation either side of its
  /// centre fits in one cell: its one or two Gaussians then turn a view
  /// about the object instead of placing it. On simulated wooden toy 2
  /// (spread 28 mm, Kinect and SR4000) leaving out the 6 cm level brings
  /// the 8 mm / 2 deg runs' median from 2.4-2.7 to 1.5-1.7 mm; the cups
  /// (32 mm) gain at 8 mm but lose at 3 or 5 mm, and objects with a long
  /// axis (bunny 45-48 mm, wooden toy 1 37-39, bottle 55) need the level
  /// (docs/reconstruction.md, "Stop 55"). Batch registration only (as
  /// scans arrive the object is not known yet).
  double model_alignment_max_cell_to_spread = 2.0;
  /// A view the first level could not place is tried again from its pose
  /// turned by this angle (radians) about the camera's y and z axes (MRPT
  /// axes: across the line of sight), the 8 combinations, the best score
  /// kept; 0: no retry. A turned start can reach a wrong basin that scores
  /// better on the coarse cells, so the second level aligns such a view
  /// also from its unturned pose and keeps the better score. On twenty
  /// seeds per class of the real views (stop 50) the runs ending above
  /// 1 mm at 8 mm / 2 deg went 25 -> 11 of 60 and the one failing 5 mm run
  /// 5.3 -> 0.79 mm, at 20 % more time at 8 mm and 2 % at 5 mm; the real
  /// recording's own poses are as they were; docs/reconstruction.md,
  /// "Stop 50".
  double model_alignment_retry_angle = 0.03;
  /// A view's model alignment is kept when its points moved at most this
  /// far (metres, at their centroid) and turned at most this much
  /// (radians) from the reported pose, and its normalised NDT score is at
  /// least `min_normalized_score`.
  double model_alignment_max_translation = 0.08;
  double model_alignment_max_rotation = 0.25;
  /// After the pose graph, a view the model alignment's last level did
  /// not keep, or one the graph left apart from the others (below), is
  /// aligned again, through the same levels (and the turned starts),
  /// against the other views, now where the graph put them: at the first
  /// level their union was blurred by every view's error, now it is sharp.
  /// At the finest level the graph's pose competes as a start: the better
  /// NDT score wins, refined against the others either way. Skipped unless
  /// the views kept outnumber the others. Batch registration only.
  bool reseat_unplaced_views = true;
  /// A view is apart when fewer than this share of the cubes of edge
  /// `reseat_overlap_cube` (metres) its points occupy are occupied by
  /// another view, and fewer than half the views' median share: a view
  /// left a centimetre or more off crosses the others' surface along a
  /// line (0.05-0.10 of its cubes on the real PrimeSense views, against
  /// 0.64-0.99 in place); also the share below which a view or group still
  /// counts as apart after its re-seat (the search). 0: no view is apart by
  /// its own share, and none is searched for. The
  /// cube's edge is scaled like the ICP's kernel for a sensor sparser than
  /// `icp_spacing_reference` (a 176 x 144 ToF camera: about 6 mm).
  double reseat_min_shared_cubes = 0.3;
  double reseat_overlap_cube = 0.004;
  /// Views off together agree with each other, not with the rest: two
  /// views are linked when they share at least this share of either one's
  /// cubes, and when the largest linked group holds most of the views, the
  /// views outside it are apart too (in place, neighbouring real views
  /// share 0.3-0.8, Stanford's scans 0.35-0.8 with their nearest; groups
  /// left apart 0.00-0.06 with the rest). Those of them linked to each
  /// other move as one rigid group (each member within the alignment's
  /// limits from its own reported pose); every other view re-seated moves
  /// alone. 0: no groups.
  double reseat_min_pair_cubes = 0.15;
  /// A view (or group) still apart after its re-seat, sharing fewer than
  /// `reseat_min_shared_cubes` of its cubes with the views kept, is
  /// searched for: the two finest model-alignment levels from starts
  /// shifted by multiples of this step (metres; up to `reseat_search_steps`
  /// along each world axis, 124 starts at 2) around its graph pose, the
  /// best final score kept. The finest levels' reach is about a centimetre,
  /// the views left apart at 8 mm / 2 deg per view 1-5 cm off. 0: no search.
  double reseat_search_step = 0.01;
  int reseat_search_steps = 2;
  /// Passes of the re-seat: a group no start of a pass seats is aligned
  /// again in the next against the views kept and the groups seated so
  /// far (only when the pass seated some). 1: one pass.
  int reseat_passes = 2;
  /// Registration as the scans arrive: add() aligns each view to the
  /// union of the earlier ones (the model alignment's levels, from its
  /// reported pose) and registers it with its best-overlapping earlier views
  /// (the first round's NDT and ICP, up to `max_partners`, and the previous
  /// view); finish() then has only the loop-closure pair, the pose graph and
  /// the later rounds left, and may be called again after more add()s.
  /// Off (default): finish() does it all, each view aligned to all the
  /// others at once, which the file paths use. The two differ: a view is
  /// aligned to the views before it, not to those after it.
  bool incremental = false;
  /// Multiway rounds: after the pose graph is solved the pairs are chosen
  /// again at the new poses (views that now overlap become partners) and
  /// registered again from the graph's relative poses (ICP only), and the
  /// graph is solved again. 1: a single round. 0 (default): two when the
  /// views are registered at once (the joint refinement after them does
  /// what a third did), three when `incremental` (its first round pairs
  /// each view with earlier views only; with two rounds the simulated
  /// Kinect cup's filtered mesh went 0.23 -> 0.32 mm from its CAD, three
  /// bring it to 0.24).
  int refinement_rounds = 0;
  /// With `refinement_rounds` automatic: a pair of the last round that
  /// the ICP matched too little of (its views beyond its reach), between
  /// views the accepted pairs leave apart, whose views that round's graph
  /// then moved farther than `unsettled_pair_move` (metres, the later
  /// rounds' ICP reach) relative to each other, was measured where they no
  /// longer are. Then every pair that would join views no accepted pair
  /// links (the last round's rejected ones and those chosen anew at the
  /// graph's poses) is registered from the graph's poses, and when one of
  /// them is accepted as a full link (every direction fixed by its
  /// surface) one more round is run (up to `max_unsettled_rounds`; 0: off)
  /// with the last round's pairs, the accepted ones as they were measured
  /// (measured again, a symmetric object's pair may slide), and the new
  /// links. On the real 9-view recording at 8 mm / 2 deg, seed 8, the
  /// second graph moved a group of views 24 mm; its worst view ended 1.6
  /// mm from the reference without this, 0.9 with it.
  double unsettled_pair_move = 0.003;
  int max_unsettled_rounds = 1;
  /// The robot's relative motions are only as good as the data says: the
  /// consecutive pairs' registered relative poses measure the odometry's
  /// error (robust spread per axis), and the odometry edges get
  /// max(`odometry_sigma_*`, measured) as their sigma; a per-view
  /// independent error (a mobile manipulator, 3 mm / 0.5 deg per view)
  /// then leaves the odometry weak instead of pulling every scan back to
  /// where the robot reported it. The reported-pose priors likewise get at
  /// least the measured per-view error (the odometry's / sqrt 2). false:
  /// trust the stated sigmas.
  bool estimate_robot_precision = true;
  /// Rounds of re-estimating the pairs' precision from their residuals
  /// (variance component estimation against the odometry and priors; the
  /// pairs are only ever weakened); 0: trust `registration_sigma_*`.
  int variance_rounds = 10;
  /// Robust kernel etc. of the final optimisation; registration and loop
  /// closure edges are robust, priors and odometry are not.
  PoseGraphParameters graph = [] {
    PoseGraphParameters p;
    p.kernel = RobustKernel::Cauchy;
    return p;
  }();

  /// Throws InputError naming the field ("model_voxel_size", ...) for a
  /// value out of range. The SequenceRegistration constructor calls it;
  /// callers may call it before reading any scan.
  void validate() const;
};

/// An absolute measurement of a scan's pose besides the robot's report (the
/// camera pose relative to a checkerboard under the object): one more prior
/// edge in the pose graph, with its own standard deviations.
struct PosePrior {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< scan -> model frame
  double sigma_translation = 0.002;                        ///< metres
  double sigma_rotation = 0.004;                           ///< radians
};

/// What happened to one scan.
struct ScanRegistrationRecord {
  std::size_t index = 0;
  std::size_t points = 0;                                          ///< handed over
  Eigen::Isometry3d initial_pose = Eigen::Isometry3d::Identity();  ///< reported
  Eigen::Isometry3d start_pose = Eigen::Isometry3d::Identity();    ///< NDT's initial guess
  Eigen::Isometry3d model_pose = Eigen::Isometry3d::Identity();    ///< after scan-to-model
  bool registered = false;  ///< false for the first scan and for rejected registrations
  std::string rejection;    ///< why a registration was rejected; empty otherwise
  double normalized_score = 0.0;
  std::vector<int> iterations;
  bool converged = false;
  int degenerate_directions = 0;          ///< unobserved directions left at the start pose
  double weakest_direction_ratio = 1.0;   ///< smallest / largest scaled Hessian eigenvalue
  double correction_translation_m = 0.0;  ///< model_pose vs initial_pose
  double correction_rotation_rad = 0.0;
  std::size_t model_points = 0;  ///< model size the scan was registered against
  double time_ms = 0.0;
};

struct LoopClosureRecord {
  bool attempted = false;
  bool accepted = false;
  std::string rejection;
  std::size_t from = 0, to = 0;  ///< first and last scan
  double normalized_score = 0.0;
  /// How far the loop closure's relative pose is from the one implied by
  /// the scan-to-model poses (the drift it corrects).
  double discrepancy_translation_m = 0.0;
  double discrepancy_rotation_rad = 0.0;
};

struct PairRegistrationRecord {
  std::size_t from = 0, to = 0;  ///< target scan, source scan
  double overlap = 0.0;          ///< shared 1 cm cubes / cubes of the smaller scan
  bool accepted = false;
  std::string rejection;
  double normalized_score = 0.0;
  int degenerate_directions = 0;
  double weakest_direction_ratio = 1.0;  ///< smallest / largest scaled Hessian eigenvalue
  /// The fine stage (when `icp_refinement`): weighted inlier fraction of
  /// the source and RMS residual along the normals (metres).
  double icp_inlier_fraction = 0.0;
  double icp_rms_m = 0.0;
  int round = 0;  ///< multiway round whose graph took the pair (0-based; an unsettled round takes the last one's)
  /// Rejected from the ICP's start, registered again with the coarse
  /// start (`SequenceRegistrationParameters::pair_ndt_retry_rejected`).
  bool retried_coarse = false;
  /// The registered pose of scan `to` in scan `from`'s frame (when accepted).
  Eigen::Isometry3d measurement = Eigen::Isometry3d::Identity();
  /// How far the pair's relative pose is from the scan-to-model poses'.
  double discrepancy_translation_m = 0.0;
  double discrepancy_rotation_rad = 0.0;
};

struct SequenceRegistrationResult {
  std::vector<Eigen::Isometry3d> poses;  ///< final, scan -> model frame, in input order
  std::vector<ScanRegistrationRecord> scans;
  LoopClosureRecord loop_closure;
  std::vector<PairRegistrationRecord> pairs;
  PoseGraphReport graph;
  std::size_t model_points = 0;  ///< final model size (voxel centroids)
  std::vector<double> resolutions;  ///< the NDT cell sizes used (metres)
  /// The sigmas the robot's odometry edges and reported-pose priors were
  /// given (stated or measured, see `estimate_robot_precision`).
  double odometry_sigma_translation_m = 0.0, odometry_sigma_rotation_rad = 0.0;
  double prior_sigma_translation_m = 0.0, prior_sigma_rotation_rad = 0.0;
  /// The robot's relative-motion error as measured by the consecutive
  /// pairs (robust sigma per axis; 0 when too few pairs).
  double measured_odometry_sigma_translation_m = 0.0, measured_odometry_sigma_rotation_rad = 0.0;
  /// Views kept / rejected by the model alignment, per level.
  std::vector<std::size_t> model_alignment_accepted;
  /// The model alignment's levels used (metres; see
  /// `model_alignment_max_cell_to_spread`) and the object's spread they were
  /// chosen by (metres; 0 when not measured).
  std::vector<double> model_alignment_resolutions;
  double model_spread_m = 0.0;
  /// Median and largest move of the views' points by the model alignment (metres).
  double model_alignment_median_move_m = 0.0, model_alignment_max_move_m = 0.0;
  /// Views aligned again after the pose graph (`reseat_unplaced_views`:
  /// unplaced or apart) and, of those, the ones whose re-seated start beat
  /// the graph's pose.
  std::size_t reseat_tried = 0, reseat_moved = 0;
  /// First-round pairs of placed views registered again with the coarse
  /// start after the ICP alone matched too little of them, between views
  /// the accepted pairs left apart (`pair_ndt_retry_rejected`), and of
  /// those the ones then accepted.
  std::size_t pairs_retried_coarse = 0, pairs_retried_accepted = 0;
  /// Of the views re-seated, those still apart that the grid searched for.
  std::size_t reseat_searched = 0;
  int refinement_rounds = 0;  ///< multiway rounds run
  /// Pairs registered for unsettled rounds (`max_unsettled_rounds`), and
  /// of those the ones accepted as full links (a round is run only when
  /// some were).
  std::size_t unsettled_pairs_registered = 0, unsettled_pairs_accepted = 0;
  /// The joint refinement (`joint_refinement`): its iterations (0: not
  /// run), pairs of views with correspondences, and weighted RMS residual.
  int joint_iterations = 0;
  std::size_t joint_pairs = 0;
  double joint_rms_m = 0.0;
  /// Unordered pairs of views its correspondences linked (and the graph's
  /// accepted pairs of its last round, each once); whether its poses
  /// were kept, and why not (empty when kept or not run).
  std::size_t joint_linked_view_pairs = 0;
  std::size_t joint_graph_view_pairs = 0;  ///< the graph's accepted pairs of its last round
  bool joint_applied = false;
  std::string joint_rejection;
  /// The pairs' variance as estimated from their residuals, relative to
  /// `registration_sigma_*` (>= 1: less precise than stated).
  double pair_variance_factor = 1.0;
  double first_scan_spacing_m = 0.0;  ///< median nearest-neighbour spacing of the first scan
  double time_ms = 0.0;          ///< registrations, loop closure and graph
  /// Where finish() spent its time (milliseconds, wall clock): each view's
  /// reduced inputs and tangent planes, the model alignment, the pairs'
  /// registrations (all rounds), the pose graphs (all rounds, with their
  /// variance estimation), the joint refinement (with its normals);
  /// `model_alignment_ms` includes the re-seat after the graph. As
  /// the scans arrive (`incremental`), the preparation, the alignment and
  /// the first round's pairs happen in add(): finish() reports the first
  /// two near 0 and `pairs_ms` holds the later rounds only; `time_ms`
  /// holds add()'s share too.
  struct StageTimes {
    double prepare_ms = 0.0, model_alignment_ms = 0.0, pairs_ms = 0.0, graph_ms = 0.0, joint_ms = 0.0;
  } stage_times;
};

class SequenceRegistration {
public:
  /// Throws InputError for parameters out of range.
  explicit SequenceRegistration(const SequenceRegistrationParameters& params = {});
  ~SequenceRegistration();
  SequenceRegistration(const SequenceRegistration&) = delete;
  SequenceRegistration& operator=(const SequenceRegistration&) = delete;

  /// Registers the next scan: `points` in the scan's own frame,
  /// `initial_pose` its reported pose (scan -> model frame), `prior` an
  /// optional independent measurement of its pose (a prior edge even when
  /// the reported poses give none). Throws InputError naming the scan for an
  /// empty cloud, a non-finite coordinate, a non-finite pose or a prior
  /// sigma <= 0. NDT failures are not errors: the scan is recorded as
  /// rejected.
  const ScanRegistrationRecord& add(const PointCloud& points, const Eigen::Isometry3d& initial_pose,
                                    const std::optional<PosePrior>& prior = std::nullopt);

  std::size_t size() const;

  /// Bytes of the point copies kept per scan (reduced points and normals;
  /// when `incremental`, also each view's NDT and ICP inputs and the ICP
  /// targets' points): what registering as the scans arrive adds to memory.
  /// The NDT cells and search trees built over them are not counted.
  std::size_t pointBytes() const;

  /// Loop closure and pose graph; the object cannot be used afterwards,
  /// unless `incremental`: then it solves from the registrations so far and
  /// more scans may follow. Throws InputError when no scan was added.
  SequenceRegistrationResult finish();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Convenience: every scan at once.
SequenceRegistrationResult registerScanSequence(const std::vector<PointCloud>& scans,
                                                const std::vector<Eigen::Isometry3d>& initial_poses,
                                                const SequenceRegistrationParameters& params = {});

}  // namespace icrkit::reconstruction

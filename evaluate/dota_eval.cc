#include "evaluate/dota_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

namespace lsds::evaluate {

namespace {

struct Point {
  double x = 0, y = 0;
};

// polyiou.cpp:9-12: the sign of d with a tolerance of 1e-8.
int Sign(double d) {
  constexpr double kEps = 1e-8;
  return (d > kEps) - (d < -kEps);
}

bool SamePoint(const Point& a, const Point& b) {
  return Sign(a.x - b.x) == 0 && Sign(a.y - b.y) == 0;
}

double Cross(const Point& o, const Point& a, const Point& b) {
  return (a.x - o.x) * (b.y - o.y) - (b.x - o.x) * (a.y - o.y);
}

// polyiou.cpp:23-30: the signed area (counter-clockwise positive in a y-up frame).
double SignedArea(const std::vector<Point>& ps) {
  double res = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Point& a = ps[i];
    const Point& b = ps[(i + 1) % ps.size()];
    res += a.x * b.y - a.y * b.x;
  }
  return res / 2.0;
}

// polyiou.cpp:31-40: where line ab meets segment cd (the caller knows they cross).
Point LineCross(const Point& a, const Point& b, const Point& c, const Point& d) {
  const double s1 = Cross(a, b, c), s2 = Cross(a, b, d);
  if (Sign(s1) == 0 && Sign(s2) == 0) return {};  // unused: returns 2 there, p unchanged
  if (Sign(s2 - s1) == 0) return {};
  return {(c.x * s2 - d.x * s1) / (s2 - s1), (c.y * s2 - d.y * s1) / (s2 - s1)};
}

// polyiou.cpp:58-71: what of polygon p lies left of line ab, repeated points
// removed.
void CutLeftOf(std::vector<Point>* p, const Point& a, const Point& b) {
  std::vector<Point> kept;
  const size_t n = p->size();
  for (size_t i = 0; i < n; ++i) {
    const Point& here = (*p)[i];
    const Point& next = (*p)[(i + 1) % n];
    if (Sign(Cross(a, b, here)) > 0) kept.push_back(here);
    if (Sign(Cross(a, b, here)) != Sign(Cross(a, b, next)))
      kept.push_back(LineCross(a, b, here, next));
  }
  p->clear();
  for (size_t i = 0; i < kept.size(); ++i)
    if (i == 0 || !SamePoint(kept[i], kept[i - 1])) p->push_back(kept[i]);
  while (p->size() > 1 && SamePoint(p->back(), p->front())) p->pop_back();
}

// polyiou.cpp:74-89: the signed intersection of triangles oab and ocd, o the
// origin.
double TriangleIntersection(Point a, Point b, Point c, Point d) {
  const Point o{0, 0};
  const int s1 = Sign(Cross(o, a, b)), s2 = Sign(Cross(o, c, d));
  if (s1 == 0 || s2 == 0) return 0.0;
  if (s1 == -1) std::swap(a, b);
  if (s2 == -1) std::swap(c, d);
  std::vector<Point> p = {o, a, b};
  CutLeftOf(&p, o, c);
  CutLeftOf(&p, c, d);
  CutLeftOf(&p, d, o);
  // area() of polyiou reads n points (0 after a full cut, 1 for a point).
  const double res = p.size() < 3 ? 0.0 : std::fabs(SignedArea(p));
  return s1 * s2 == -1 ? -res : res;
}

std::vector<Point> Corners(const Quad& q) {
  std::vector<Point> ps(4);
  for (size_t i = 0; i < 4; ++i) ps[i] = {q[i * 2], q[i * 2 + 1]};
  return ps;
}

// The upright box of a quad (task1.py:201-208).
struct Upright {
  double xmin, ymin, xmax, ymax;
};
Upright UprightOf(const Quad& q) {
  Upright u{q[0], q[1], q[0], q[1]};
  for (size_t i = 1; i < 4; ++i) {
    u.xmin = std::min(u.xmin, q[i * 2]);
    u.xmax = std::max(u.xmax, q[i * 2]);
    u.ymin = std::min(u.ymin, q[i * 2 + 1]);
    u.ymax = std::max(u.ymax, q[i * 2 + 1]);
  }
  return u;
}

// task1.py:210-225: the upright boxes' IoU with VOC's +1 pixel, > 0 to go on.
bool UprightOverlap(const Upright& g, const Upright& d) {
  const double iw = std::max(std::min(g.xmax, d.xmax) - std::max(g.xmin, d.xmin) + 1., 0.);
  const double ih = std::max(std::min(g.ymax, d.ymax) - std::max(g.ymin, d.ymin) + 1., 0.);
  const double inters = iw * ih;
  const double uni = (d.xmax - d.xmin + 1.) * (d.ymax - d.ymin + 1.) +
                     (g.xmax - g.xmin + 1.) * (g.ymax - g.ymin + 1.) - inters;
  return inters / uni > 0;
}

// voc_ap (task1.py:54-85).
double VocAveragePrecision(const std::vector<double>& rec,
                           const std::vector<double>& prec,
                           VocAp ap) {
  if (ap == VocAp::k07) {
    double sum = 0;
    // np.arange(0., 1.1, 0.1): i * 0.1 as numpy computes it.
    for (int i = 0; i < 11; ++i) {
      const double t = static_cast<double>(i) * 0.1;
      double p = 0;
      bool any = false;
      for (size_t k = 0; k < rec.size(); ++k) {
        if (rec[k] >= t) p = any ? std::max(p, prec[k]) : prec[k], any = true;
      }
      sum = sum + p / 11.;
    }
    return sum;
  }
  std::vector<double> mrec = {0.}, mpre = {0.};
  mrec.insert(mrec.end(), rec.begin(), rec.end());
  mpre.insert(mpre.end(), prec.begin(), prec.end());
  mrec.push_back(1.);
  mpre.push_back(0.);
  for (size_t i = mpre.size() - 1; i > 0; --i) mpre[i - 1] = std::max(mpre[i - 1], mpre[i]);
  // np.sum over the points where recall changes (pairwise summation in numpy;
  // a plain sum differs by rounding only).
  double sum = 0;
  for (size_t i = 0; i + 1 < mrec.size(); ++i)
    if (mrec[i + 1] != mrec[i]) sum += (mrec[i + 1] - mrec[i]) * mpre[i + 1];
  return sum;
}

DotaClassResult EvaluateClass(const std::string& class_name,
                              const std::vector<DotaObject>& objects,
                              const std::vector<DotaDetection>& detections,
                              VocAp ap,
                              double iou_threshold) {
  DotaClassResult result;
  result.class_name = class_name;
  // class_recs (task1.py:146-156): the class's objects per image, file order.
  std::map<std::string, std::vector<const DotaObject*>> by_image;
  for (const DotaObject& o : objects) {
    if (o.class_name != class_name) continue;
    by_image[o.image].push_back(&o);
    (o.difficult ? result.difficult : result.objects) += 1;
  }
  std::map<const DotaObject*, bool> taken;
  std::vector<const DotaDetection*> dets;
  for (const DotaDetection& d : detections)
    if (d.class_name == class_name) dets.push_back(&d);
  result.detections = static_cast<int64_t>(dets.size());
  std::stable_sort(dets.begin(), dets.end(), [](const DotaDetection* a, const DotaDetection* b) {
    return -a->score < -b->score;
  });
  std::vector<double> tp(dets.size(), 0), fp(dets.size(), 0);
  for (size_t d = 0; d < dets.size(); ++d) {
    const DotaDetection& det = *dets[d];
    double ovmax = -std::numeric_limits<double>::infinity();
    const DotaObject* best = nullptr;
    const auto it = by_image.find(det.image);
    if (it != by_image.end()) {
      const Upright u = UprightOf(det.quad);
      for (const DotaObject* g : it->second) {
        if (!UprightOverlap(UprightOf(g->quad), u)) continue;
        // polyiou.iou_poly(BBGT, bb), the first of the highest (np.argmax).
        const double overlap = QuadIou(g->quad, det.quad);
        if (best == nullptr || overlap > ovmax) ovmax = overlap, best = g;
      }
    }
    // task1.py:244-252.
    if (ovmax > iou_threshold) {
      if (!best->difficult) {
        if (!taken[best]) {
          tp[d] = 1.;
          taken[best] = true;
        } else {
          fp[d] = 1.;
        }
      }
    } else {
      fp[d] = 1.;
    }
  }
  result.true_positives = static_cast<int64_t>(std::accumulate(tp.begin(), tp.end(), 0.0));
  if (result.objects == 0) return result;
  // task1.py:261-268.
  std::vector<double> rec(dets.size()), prec(dets.size());
  double ctp = 0, cfp = 0;
  for (size_t i = 0; i < dets.size(); ++i) {
    ctp += tp[i];
    cfp += fp[i];
    rec[i] = ctp / static_cast<double>(result.objects);
    prec[i] = ctp / std::max(ctp + cfp, std::numeric_limits<double>::epsilon());
  }
  result.ap = VocAveragePrecision(rec, prec, ap);
  return result;
}

}  // namespace

double QuadIou(const Quad& p, const Quad& q) {
  std::vector<Point> ps1 = Corners(p), ps2 = Corners(q);
  // intersectArea (polyiou.cpp:91-103): both made counter-clockwise, then
  // every pair of fan triangles from the origin.
  if (SignedArea(ps1) < 0) std::reverse(ps1.begin(), ps1.end());
  if (SignedArea(ps2) < 0) std::reverse(ps2.begin(), ps2.end());
  double inter = 0;
  for (size_t i = 0; i < 4; ++i)
    for (size_t j = 0; j < 4; ++j)
      inter += TriangleIntersection(ps1[i], ps1[(i + 1) % 4], ps2[j], ps2[(j + 1) % 4]);
  const double united = std::fabs(SignedArea(ps1)) + std::fabs(SignedArea(ps2)) - inter;
  return inter / united;  // polyiou.cpp:119-121
}

double QuadArea(const Quad& q) { return std::fabs(SignedArea(Corners(q))); }

namespace {

BoxXywh UprightBox(const Quad& q) {
  const Upright u = UprightOf(q);
  return {u.xmin, u.ymin, u.xmax - u.xmin, u.ymax - u.ymin};
}

int64_t CategoryOf(const std::vector<std::string>& class_names, const std::string& name) {
  const auto it = std::find(class_names.begin(), class_names.end(), name);
  return it == class_names.end() ? 0 : static_cast<int64_t>(it - class_names.begin()) + 1;
}

}  // namespace

CocoData DotaAsCoco(const std::vector<std::string>& class_names,
                    const std::vector<DotaObject>& objects,
                    const std::vector<DotaDetection>& detections,
                    const std::map<std::string, int64_t>& image_ids) {
  CocoData data;
  data.iou_type = IouType::kQuad;
  for (const auto& [stem, id] : image_ids) data.image_ids.push_back(id);
  for (size_t c = 0; c < class_names.size(); ++c) data.category_ids.push_back(int64_t(c) + 1);
  const auto image_of = [&](const std::string& stem) {
    const auto it = image_ids.find(stem);
    return it == image_ids.end() ? int64_t{0} : it->second;
  };
  for (const DotaObject& o : objects) {
    GroundTruthBox g;
    g.id = static_cast<int64_t>(data.ground_truth.size()) + 1;
    g.image_id = image_of(o.image);
    g.category_id = CategoryOf(class_names, o.class_name);
    g.bbox = UprightBox(o.quad);
    g.area = QuadArea(o.quad);
    g.ignored = o.difficult;
    g.quad.assign(o.quad.begin(), o.quad.end());
    data.ground_truth.push_back(std::move(g));
  }
  for (const DotaDetection& d : detections) {
    DetectionBox b;
    b.image_id = image_of(d.image);
    b.category_id = CategoryOf(class_names, d.class_name);
    b.bbox = UprightBox(d.quad);
    b.score = d.score;
    b.area = QuadArea(d.quad);
    b.quad.assign(d.quad.begin(), d.quad.end());
    data.detections.push_back(std::move(b));
  }
  return data;
}

DotaResult EvaluateDota(const std::vector<std::string>& class_names,
                        const std::vector<DotaObject>& objects,
                        const std::vector<DotaDetection>& detections,
                        VocAp ap,
                        double iou_threshold) {
  DotaResult result;
  result.ap = ap;
  result.iou_threshold = iou_threshold;
  double sum = 0;
  int n = 0;
  for (const std::string& name : class_names) {
    result.classes.push_back(EvaluateClass(name, objects, detections, ap, iou_threshold));
    if (result.classes.back().ap) sum += *result.classes.back().ap, ++n;
  }
  if (n > 0) result.map = sum / n;  // task1.py:312
  return result;
}

}  // namespace lsds::evaluate

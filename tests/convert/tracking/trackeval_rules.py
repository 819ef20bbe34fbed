"""TrackEval's MOTChallenge ground-truth loading, preprocessing and its HOTA, CLEAR (MOTA) and
Identity (IDF1) metrics, ported (not copied) from JonathonLuiten/TrackEval at commit 12c8791 with
the source file and line of each rule named. Only what box ground truth in the MOT17 layout needs:
no zip input, no crowd ignore regions (MOTChallenge has none, mot_challenge_2d_box.py:319)."""
import configparser
import csv
import os

import numpy as np
from scipy.optimize import linear_sum_assignment

EPS = np.finfo('float').eps

# trackeval/datasets/mot_challenge_2d_box.py:76-78
CLASS_NAME_TO_ID = {'pedestrian': 1, 'person_on_vehicle': 2, 'car': 3, 'bicycle': 4, 'motorbike': 5,
                    'non_mot_vehicle': 6, 'static_person': 7, 'distractor': 8, 'occluder': 9,
                    'occluder_on_ground': 10, 'occluder_full': 11, 'reflection': 12, 'crowd': 13}
# mot_challenge_2d_box.py:325-328 (MOT17: non_mot_vehicle is a distractor only in MOT20)
DISTRACTOR_IDS = [CLASS_NAME_TO_ID[n]
                  for n in ('person_on_vehicle', 'static_person', 'distractor', 'reflection')]


class TrackEvalError(Exception):
    pass


def sequences(gt_folder, benchmark, split):
    """Sequence names and lengths: the seqmap GT_FOLDER/seqmaps/BENCHMARK-SPLIT.txt, first line
    skipped (mot_challenge_2d_box.py:50,153,159-165), seqLength from each seqinfo.ini (:166-171)."""
    gt_set = benchmark + '-' + split
    seqmap = os.path.join(gt_folder, 'seqmaps', gt_set + '.txt')
    if not os.path.isfile(seqmap):
        raise TrackEvalError('no seqmap found: ' + seqmap)
    lengths = {}
    with open(seqmap) as fp:
        for i, row in enumerate(csv.reader(fp)):
            if i == 0 or row[0] == '':
                continue
            ini = os.path.join(gt_folder, gt_set, row[0], 'seqinfo.ini')
            if not os.path.isfile(ini):
                raise TrackEvalError('ini file does not exist: ' + ini)
            data = configparser.ConfigParser()
            data.read(ini)
            lengths[row[0]] = int(data['Sequence']['seqLength'])
    return lengths


def load_simple_text_file(path):
    """Rows per timestep (strings), as _base_dataset.py:105-212 reads them: the delimiter sniffed
    from the first line (:159), spaces after delimiters skipped (:160), a trailing empty column
    dropped (:166-167), the timestep the int of column 0 (:168)."""
    read = {}
    with open(path) as fp:
        fp.seek(0, os.SEEK_END)
        if not fp.tell():
            return read
        fp.seek(0)
        dialect = csv.Sniffer().sniff(fp.readline())
        dialect.skipinitialspace = True
        fp.seek(0)
        for row in csv.reader(fp, dialect):
            if row[-1] in '':
                row = row[:-1]
            read.setdefault(str(int(float(row[0]))), []).append(row)
    return read


def load_raw(path, seq, num_timesteps, is_gt):
    """mot_challenge_2d_box.py:200-287: frames must be 1..seqLength (:213-222), columns 2:6 the box
    xywh, 1 the id, 7 the class (gt needs >= 8 columns, :249-257), 6 zero_marked (gt) or the
    confidence (tracker, :258-262)."""
    read = load_simple_text_file(path)
    valid = {str(t + 1) for t in range(num_timesteps)}
    extra = [k for k in read if k not in valid]
    if extra:
        raise TrackEvalError('%s data contains the following invalid timesteps in seq %s: %s'
                             % ('Ground-truth' if is_gt else 'Tracking', seq, ', '.join(extra)))
    raw = {'ids': [], 'classes': [], 'dets': [], 'extra': []}
    for t in range(num_timesteps):
        rows = read.get(str(t + 1))
        if rows is None:
            raw['dets'].append(np.empty((0, 4)))
            raw['ids'].append(np.empty(0).astype(int))
            raw['classes'].append(np.empty(0).astype(int))
            raw['extra'].append(np.empty(0))
            continue
        data = np.asarray(rows, dtype=float)
        raw['dets'].append(np.atleast_2d(data[:, 2:6]))
        raw['ids'].append(np.atleast_1d(data[:, 1]).astype(int))
        if data.shape[1] >= 8:
            raw['classes'].append(np.atleast_1d(data[:, 7]).astype(int))
        elif not is_gt:
            raw['classes'].append(np.ones_like(raw['ids'][-1]))
        else:
            raise TrackEvalError('GT data is not in a valid format in seq %s, timestep %d' % (seq, t))
        raw['extra'].append(np.atleast_1d(data[:, 6].astype(int)) if is_gt
                            else np.atleast_1d(data[:, 6]))
    return raw


def box_ious(boxes1, boxes2):
    """_base_dataset.py:248-286, box_format 'xywh', IoU."""
    b1 = np.array(boxes1, dtype=float).reshape(-1, 4).copy()
    b2 = np.array(boxes2, dtype=float).reshape(-1, 4).copy()
    b1[:, 2] += b1[:, 0]
    b1[:, 3] += b1[:, 1]
    b2[:, 2] += b2[:, 0]
    b2[:, 3] += b2[:, 1]
    mn = np.minimum(b1[:, np.newaxis, :], b2[np.newaxis, :, :])
    mx = np.maximum(b1[:, np.newaxis, :], b2[np.newaxis, :, :])
    inter = np.maximum(mn[..., 2] - mx[..., 0], 0) * np.maximum(mn[..., 3] - mx[..., 1], 0)
    area1 = (b1[..., 2] - b1[..., 0]) * (b1[..., 3] - b1[..., 1])
    area2 = (b2[..., 2] - b2[..., 0]) * (b2[..., 3] - b2[..., 1])
    union = area1[:, np.newaxis] + area2[np.newaxis, :] - inter
    inter[area1 <= 0 + EPS, :] = 0
    inter[:, area2 <= 0 + EPS] = 0
    inter[union <= 0 + EPS] = 0
    union[union <= 0 + EPS] = 1
    return inter / union


def check_unique_ids(ids_per_t, seq, what):
    """_base_dataset.py:300-325: an id at most once per timestep."""
    for t, ids in enumerate(ids_per_t):
        if len(ids) > 0:
            _, counts = np.unique(ids, return_counts=True)
            if np.max(counts) != 1:
                raise TrackEvalError('%s has the same ID more than once in a single timestep '
                                     '(seq: %s, frame: %d)' % (what, seq, t + 1))


def preprocess(gt, tr, seq, cls_id=1):
    """mot_challenge_2d_box.py:290-433 (MOT17, DO_PREPROC on): tracker classes above 1 rejected
    (:351-355), gt classes outside 1..13 rejected (:362-371), tracker boxes matched (IoU >= 0.5,
    Hungarian) to distractor gt removed (:373-387), gt kept only when not zero-marked and of the
    evaluated class (:391-399), ids relabelled 0.. (:406-420)."""
    check_unique_ids(gt['ids'], seq, 'Ground-truth')
    check_unique_ids(tr['ids'], seq, 'Tracker')
    n = len(gt['ids'])
    data = {'gt_ids': [], 'tracker_ids': [], 'similarity_scores': []}
    gt_seen, tr_seen = [], []
    num_gt = num_tr = 0
    for t in range(n):
        gt_ids, gt_dets, gt_classes, zero = gt['ids'][t], gt['dets'][t], gt['classes'][t], gt['extra'][t]
        tr_ids, tr_dets, tr_classes = tr['ids'][t], tr['dets'][t], tr['classes'][t]
        sim = box_ious(gt_dets, tr_dets)  # mot_challenge_2d_box.py:435-437
        if len(tr_classes) > 0 and np.max(tr_classes) > 1:
            raise TrackEvalError('Evaluation is only valid for pedestrian class (seq %s, t %d)' % (seq, t))
        remove = np.array([], int)
        if gt_ids.shape[0] > 0 and tr_ids.shape[0] > 0:
            invalid = np.setdiff1d(np.unique(gt_classes), list(CLASS_NAME_TO_ID.values()))
            if len(invalid) > 0:
                raise TrackEvalError('invalid gt classes %s in seq %s, timestep %d' % (invalid, seq, t))
            scores = sim.copy()
            scores[scores < 0.5 - EPS] = 0
            rows, cols = linear_sum_assignment(-scores)
            matched = scores[rows, cols] > 0 + EPS
            rows, cols = rows[matched], cols[matched]
            remove = cols[np.isin(gt_classes[rows], DISTRACTOR_IDS)]
        tr_ids = np.delete(tr_ids, remove, axis=0)
        sim = np.delete(sim, remove, axis=1)
        keep = np.not_equal(zero, 0) & np.equal(gt_classes, cls_id)
        data['gt_ids'].append(gt_ids[keep])
        data['tracker_ids'].append(tr_ids)
        data['similarity_scores'].append(sim[keep])
        gt_seen += list(np.unique(gt_ids[keep]))
        tr_seen += list(np.unique(tr_ids))
        num_gt += int(np.sum(keep))
        num_tr += len(tr_ids)
    for key, seen in (('gt_ids', gt_seen), ('tracker_ids', tr_seen)):
        if seen:
            unique = np.unique(seen)
            relabel = np.nan * np.ones(np.max(unique) + 1)
            relabel[unique] = np.arange(len(unique))
            data[key] = [relabel[ids].astype(int) if len(ids) > 0 else ids for ids in data[key]]
    data['num_gt_dets'], data['num_tracker_dets'] = num_gt, num_tr
    data['num_gt_ids'], data['num_tracker_ids'] = len(np.unique(gt_seen)), len(np.unique(tr_seen))
    data['num_timesteps'] = n
    return data


def hota(data):
    """trackeval/metrics/hota.py:25-117 and :166-179; the reported HOTA is the mean over the 19
    localisation thresholds alpha = 0.05..0.95 (:17)."""
    alphas = np.arange(0.05, 0.99, 0.05)
    tp, fn, fp = np.zeros(len(alphas)), np.zeros(len(alphas)), np.zeros(len(alphas))
    if data['num_tracker_dets'] == 0 or data['num_gt_dets'] == 0:
        return 0.0
    potential = np.zeros((data['num_gt_ids'], data['num_tracker_ids']))
    gt_count = np.zeros((data['num_gt_ids'], 1))
    tr_count = np.zeros((1, data['num_tracker_ids']))
    for gt_ids, tr_ids, sim in zip(data['gt_ids'], data['tracker_ids'], data['similarity_scores']):
        denom = sim.sum(0)[np.newaxis, :] + sim.sum(1)[:, np.newaxis] - sim
        sim_iou = np.zeros_like(sim)
        mask = denom > 0 + EPS
        sim_iou[mask] = sim[mask] / denom[mask]
        potential[gt_ids[:, np.newaxis], tr_ids[np.newaxis, :]] += sim_iou
        gt_count[gt_ids] += 1
        tr_count[0, tr_ids] += 1
    alignment = potential / (gt_count + tr_count - potential)
    matches = [np.zeros_like(potential) for _ in alphas]
    for gt_ids, tr_ids, sim in zip(data['gt_ids'], data['tracker_ids'], data['similarity_scores']):
        if len(gt_ids) == 0:
            fp += len(tr_ids)
            continue
        if len(tr_ids) == 0:
            fn += len(gt_ids)
            continue
        score = alignment[gt_ids[:, np.newaxis], tr_ids[np.newaxis, :]] * sim
        rows, cols = linear_sum_assignment(-score)
        for a, alpha in enumerate(alphas):
            ok = sim[rows, cols] >= alpha - EPS
            r, c = rows[ok], cols[ok]
            tp[a] += len(r)
            fn[a] += len(gt_ids) - len(r)
            fp[a] += len(tr_ids) - len(r)
            matches[a][gt_ids[r], tr_ids[c]] += 1
    ass_a = np.zeros(len(alphas))
    for a in range(len(alphas)):
        m = matches[a]
        ass_a[a] = np.sum(m * (m / np.maximum(1, gt_count + tr_count - m))) / np.maximum(1, tp[a])
    det_a = tp / np.maximum(1, tp + fn + fp)
    return float(np.mean(np.sqrt(det_a * ass_a)))


def clear(data, threshold=0.5):
    """trackeval/metrics/clear.py:37-129 (THRESHOLD 0.5, :15) and MOTA (:178); returns (MOTA, IDSW)."""
    if data['num_tracker_dets'] == 0 or data['num_gt_dets'] == 0:
        return 0.0, 0  # returned before the final fields (:46-54): MOTA stays 0
    tp = fn = fp = idsw = 0
    prev_tracker = np.nan * np.zeros(data['num_gt_ids'])
    prev_step_tracker = np.nan * np.zeros(data['num_gt_ids'])
    for gt_ids, tr_ids, sim in zip(data['gt_ids'], data['tracker_ids'], data['similarity_scores']):
        if len(gt_ids) == 0:
            fp += len(tr_ids)
            continue
        if len(tr_ids) == 0:
            fn += len(gt_ids)
            continue
        score = (tr_ids[np.newaxis, :] == prev_step_tracker[gt_ids[:, np.newaxis]])
        score = 1000 * score + sim
        score[sim < threshold - EPS] = 0
        rows, cols = linear_sum_assignment(-score)
        ok = score[rows, cols] > 0 + EPS
        rows, cols = rows[ok], cols[ok]
        matched_gt, matched_tr = gt_ids[rows], tr_ids[cols]
        prev = prev_tracker[matched_gt]
        idsw += int(np.sum(np.logical_not(np.isnan(prev)) & np.not_equal(matched_tr, prev)))
        prev_tracker[matched_gt] = matched_tr
        prev_step_tracker[:] = np.nan
        prev_step_tracker[matched_gt] = matched_tr
        tp += len(matched_gt)
        fn += len(gt_ids) - len(matched_gt)
        fp += len(tr_ids) - len(matched_gt)
    return (tp - fp - idsw) / max(1.0, tp + fn), idsw


def identity(data, threshold=0.5):
    """trackeval/metrics/identity.py:31-89 (THRESHOLD 0.5) and IDF1 (:134)."""
    if data['num_tracker_dets'] == 0 or data['num_gt_dets'] == 0:
        return 0.0
    ng, nt = data['num_gt_ids'], data['num_tracker_ids']
    potential = np.zeros((ng, nt))
    gt_count, tr_count = np.zeros(ng), np.zeros(nt)
    for gt_ids, tr_ids, sim in zip(data['gt_ids'], data['tracker_ids'], data['similarity_scores']):
        g, k = np.nonzero(np.greater_equal(sim, threshold))
        potential[gt_ids[g], tr_ids[k]] += 1
        gt_count[gt_ids] += 1
        tr_count[tr_ids] += 1
    fp_mat = np.zeros((ng + nt, ng + nt))
    fn_mat = np.zeros((ng + nt, ng + nt))
    fp_mat[ng:, :nt] = 1e10
    fn_mat[:ng, nt:] = 1e10
    for g in range(ng):
        fn_mat[g, :nt] = gt_count[g]
        fn_mat[g, nt + g] = gt_count[g]
    for k in range(nt):
        fp_mat[:ng, k] = tr_count[k]
        fp_mat[k + ng, k] = tr_count[k]
    fn_mat[:ng, :nt] -= potential
    fp_mat[:ng, :nt] -= potential
    rows, cols = linear_sum_assignment(fn_mat + fp_mat)
    idfn = fn_mat[rows, cols].sum()
    idfp = fp_mat[rows, cols].sum()
    idtp = gt_count.sum() - idfn
    return float(idtp / max(1.0, idtp + 0.5 * idfp + 0.5 * idfn))

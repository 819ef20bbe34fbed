#!/usr/bin/env python3
"""End to end: a generated capture of cars on a road (road.lscene, road.lcap: a car passing behind
a parked truck and leaving the view, another entering it) converted to mot, visdrone and
visdrone-vid, then

- every MOT, VisDrone-VID and VisDrone row checked against the collection's truth by the rules of
  docs/convert.md (1-based frames and boxes, ids by first appearance, amodal boxes, visibility x
  in_frame, truncation and occlusion levels, categories);
- the MOT ground truth loaded and scored by TrackEval's rules (trackeval_rules.py, ported from
  TrackEval with its lines named): the ground truth as the tracker gives HOTA = MOTA = IDF1 = 1 in
  every sequence, and the same tracker with two ids swapped in one frame scores below 1;
- with --mot-classes mot17, the walker (class person) is MOT17's pedestrian (1), the cars are 3,
  and the truck, which MOT17 has no id for, is left out and counted in the loss report.

Usage: trackeval_test.py LSDS WORK"""
import configparser
import json
import os
import shutil
import subprocess
import sys

try:
    import trackeval_rules as te
except ImportError as error:
    # numpy or scipy missing: scripts/install-deps.sh installs Debian's, for the system python,
    # which may not be the first python3 on the PATH (pyenv).
    if os.path.exists('/usr/bin/python3') and os.path.realpath(sys.executable) != '/usr/bin/python3':
        os.execv('/usr/bin/python3', ['/usr/bin/python3'] + sys.argv)
    print('skipped: %s' % error)
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))
FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)
        print('FAIL: ' + message)


def run(*args):
    result = subprocess.run(list(args), capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit('%s failed (%d):\n%s%s' % (' '.join(args), result.returncode, result.stdout,
                                            result.stderr))
    return result.stdout


def read_csv(path, header=True):
    with open(path) as f:
        lines = [line.rstrip('\n') for line in f if line.strip()]
    return [line.split(',') for line in (lines[1:] if header else lines)]


def collection_frames(collection):
    with open(os.path.join(collection, 'collection.json')) as f:
        data = json.load(f)
    classes = {c['id']: c['name'] for c in data['classes']}
    return {frame['index']: frame for frame in data['frames']}, classes


def visible(obj):
    return obj.get('bbox') is not None and obj.get('visible_pixels', 0) > 0


def percent(ratio):
    # VisDrone's levels are on ratios in percent, rounded half away from zero (docs/convert.md).
    return int(100 * min(max(ratio, 0.0), 1.0) + 0.5)


def visdrone_columns(obj, category):
    """VisDrone's columns after the ids, from the truth by the VisDrone readme's rules."""
    x0, y0, x1, y1 = obj['bbox']
    truncation = 0 if percent(1 - obj['in_frame']) == 0 else 1  # "0%" / "1%~50%"
    occluded = percent(1 - obj['visibility'])
    occlusion = 0 if occluded == 0 else 1 if occluded <= 50 else 2  # 0%, 1-50%, 50-100%
    return [str(int(round(v))) for v in (x0, y0, x1 - x0, y1 - y0)] + \
        ['1', str(category), str(truncation), str(occlusion)]


VISDRONE = {'car': 4, 'truck': 6, 'person': 1}  # VisDrone readme: 1 pedestrian, 4 car, 6 truck


def check_mot_rows(out, frames, classes, mot_class_of, min_visibility=0, split='train'):
    """Every visible object of a selected class is one row of its sequence, conf 0 (ignore) when
    --min-visibility dropped it; returns the sequences."""
    root = os.path.join(out, 'mot')
    lengths = te.sequences(root, 'LSDS', split)
    check(len(lengths) > 0, 'no MOT sequence')
    for seq, length in lengths.items():
        folder = os.path.join(root, 'LSDS-' + split, seq)
        ini = configparser.ConfigParser()
        ini.read(os.path.join(folder, 'seqinfo.ini'))
        s = ini['Sequence']
        numbers = {int(r[0]): int(r[1]) for r in read_csv(os.path.join(folder, 'frames.txt'))}
        check(sorted(numbers) == list(range(1, length + 1)), seq + ': frames.txt is not 1..seqLength')
        first = frames[numbers[1]]
        check(s['name'] == seq and s['imDir'] == 'img1' and s['imExt'] == '.png',
              seq + ': seqinfo name/imDir/imExt')
        check(int(s['imWidth']) == first['camera']['width'] and
              int(s['imHeight']) == first['camera']['height'], seq + ': image size')
        if length > 1:
            step = frames[numbers[2]]['time'] - frames[numbers[1]]['time']
            check(abs(float(s['frameRate']) - 1 / step) < 1e-3, seq + ': frameRate %s' % s['frameRate'])
        ids = {int(r[1]): int(r[0]) for r in read_csv(os.path.join(folder, 'gt', 'instance_ids.txt'))}
        expected = {}
        order = []
        for n in range(1, length + 1):
            frame = frames[numbers[n]]
            image = os.path.join(folder, 'img1', '%06d.png' % n)
            shared = os.path.join(out, 'images', split, '%06d.png' % frame['index'])
            check(os.path.isfile(image) and os.path.samefile(image, shared),
                  seq + ': img1 image %d is not the shared image' % n)
            for obj in frame['objects']:
                name = classes[obj['class_id']]
                if not visible(obj) or mot_class_of(name) is None:
                    continue
                if obj['instance_id'] not in order:
                    order.append(obj['instance_id'])
                x0, y0, x1, y1 = obj.get('bbox_projected') or obj['bbox']
                expected[(n, obj['instance_id'])] = (
                    [x0 + 1, y0 + 1, x1 - x0, y1 - y0], mot_class_of(name),
                    obj['visibility'] * obj['in_frame'],
                    '1' if obj['visibility'] >= min_visibility else '0')
        # Track ids 1.. by first appearance in the sequence.
        check([ids[i] for i in order] == list(range(1, len(order) + 1)),
              seq + ': track ids are not 1.. by first appearance')
        rows = read_csv(os.path.join(folder, 'gt', 'gt.txt'), header=False)
        check(len(rows) == len(expected), seq + ': %d rows, %d visible objects' % (len(rows), len(expected)))
        for r in rows:
            check(len(r) == 9, seq + ': a gt row without 9 columns')
            instance = {v: k for k, v in ids.items()}[int(r[1])]
            want = expected.get((int(r[0]), instance))
            if want is None:
                check(False, seq + ': unexpected row ' + ','.join(r))
                continue
            box, cls, vis, conf = want
            check(all(abs(float(a) - b) < 0.006 for a, b in zip(r[2:6], box)),
                  seq + ': box %s, expected %s' % (r[2:6], box))
            check(r[6] == conf and int(r[7]) == cls and abs(float(r[8]) - vis) < 6e-6,
                  seq + ': conf/class/visibility %s, expected %s,%d,%f' % (r[6:9], conf, cls, vis))
    return lengths


def score_sequences(out, lengths, perturb=True, split='train'):
    """TrackEval's MOT17 evaluation of the ground truth as its own tracker, and of a perturbed one."""
    root = os.path.join(out, 'mot')
    perturbed_once = False
    for seq, length in lengths.items():
        gt_path = os.path.join(root, 'LSDS-' + split, seq, 'gt', 'gt.txt')
        gt = te.load_raw(gt_path, seq, length, is_gt=True)
        # A perfect tracker: the considered class-1 rows, as a tracker file (conf 1, class 1).
        rows = [r for r in read_csv(gt_path, header=False) if r[6] == '1' and r[7] == '1']
        tracker_dir = os.path.join(out, 'trackers', 'LSDS-' + split, 'self', 'data')
        os.makedirs(tracker_dir, exist_ok=True)
        tracker_path = os.path.join(tracker_dir, seq + '.txt')
        with open(tracker_path, 'w') as f:
            f.writelines(','.join(r[:7] + ['1', '-1', '-1']) + '\n' for r in rows)
        tr = te.load_raw(tracker_path, seq, length, is_gt=False)
        data = te.preprocess(gt, tr, seq)
        check(data['num_gt_dets'] > 0, seq + ': no class-1 ground truth to score')
        h, (mota, idsw), idf1 = te.hota(data), te.clear(data), te.identity(data)
        print('%s: %d gt boxes, %d ids: HOTA %.6f MOTA %.6f IDF1 %.6f' %
              (seq, data['num_gt_dets'], data['num_gt_ids'], h, mota, idf1))
        check(abs(h - 1) < 1e-9 and mota == 1 and abs(idf1 - 1) < 1e-12,
              seq + ': gt against itself: HOTA %f MOTA %f IDF1 %f' % (h, mota, idf1))
        # The same tracker with the ids of two boxes swapped in one frame (the middle one that has
        # two): an identity switch the metrics must see.
        by_frame = {}
        for r in rows:
            by_frame.setdefault(r[0], []).append(r)
        pairs = [f for f, rs in by_frame.items() if len(rs) >= 2]
        if not pairs or not perturb:
            continue
        frame = pairs[len(pairs) // 2]
        a, b = by_frame[frame][0], by_frame[frame][1]
        a[1], b[1] = b[1], a[1]
        with open(tracker_path, 'w') as f:
            f.writelines(','.join(r[:7] + ['1', '-1', '-1']) + '\n' for r in rows)
        data = te.preprocess(gt, te.load_raw(tracker_path, seq, length, is_gt=False), seq)
        h, (mota, idsw), idf1 = te.hota(data), te.clear(data), te.identity(data)
        print('%s, ids swapped in frame %s: HOTA %.6f MOTA %.6f (IDSW %d) IDF1 %.6f' %
              (seq, frame, h, mota, idsw, idf1))
        check(h < 1 and mota < 1 and idsw > 0 and idf1 < 1,
              seq + ': swapped ids not seen: HOTA %f MOTA %f IDF1 %f' % (h, mota, idf1))
        perturbed_once = True
    check(perturbed_once or not perturb, 'no frame with two class-1 boxes: the perturbation was never tried')


def check_visdrone(out, frames, classes, lengths, split='train'):
    """VisDrone DET rows per frame and VID rows per sequence, against the truth."""
    mapping = read_csv(os.path.join(out, 'visdrone', 'classes.txt'))
    check({r[0]: int(r[1]) for r in mapping} == VISDRONE, 'visdrone classes.txt %s' % mapping)
    det = {}
    for index, frame in frames.items():
        want = [visdrone_columns(o, VISDRONE[classes[o['class_id']]])
                for o in frame['objects'] if visible(o)]
        got = read_csv(os.path.join(out, 'visdrone', split, 'annotations', '%06d.txt' % index),
                       header=False)
        check(got == want, 'visdrone frame %d: %s, expected %s' % (index, got, want))
        det[index] = got
        check(os.path.samefile(os.path.join(out, 'visdrone', split, 'images', '%06d.png' % index),
                               os.path.join(out, 'images', split, '%06d.png' % index)),
              'visdrone image %d is not the shared image' % index)
    # VID: the DET columns of the frame, after frame_index (1..) and target_id (the MOT id here,
    # both numbered by first appearance in the sequence).
    for seq, length in lengths.items():
        numbers = {int(r[0]): int(r[1]) for r in
                   read_csv(os.path.join(out, 'visdrone-vid', split, 'frames', seq + '.txt'))}
        check(sorted(numbers) == list(range(1, length + 1)), seq + ': VID frames')
        rows = read_csv(os.path.join(out, 'visdrone-vid', split, 'annotations', seq + '.txt'),
                        header=False)
        for n in range(1, length + 1):
            got = [r[2:] for r in rows if int(r[0]) == n]
            check(got == det[numbers[n]], seq + ': VID frame %d differs from DET' % n)
            check(os.path.isfile(os.path.join(out, 'visdrone-vid', split, 'sequences', seq,
                                              '%07d.png' % n)), seq + ': VID image %d' % n)
        mot = read_csv(os.path.join(out, 'mot', 'LSDS-' + split, seq, 'gt', 'gt.txt'), header=False)
        check(sorted((int(r[0]), int(r[1])) for r in rows) ==
              sorted((int(r[0]), int(r[1])) for r in mot), seq + ': VID ids differ from MOT ids')
    levels = [(r[6], r[7]) for rs in det.values() for r in rs]
    check(any(t == '1' for t, _ in levels), 'no truncated object: the capture does not test it')
    check(any(o != '0' for _, o in levels), 'no occluded object: the capture does not test it')


def main():
    lsds, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    collection = os.path.join(work, 'collection')
    run(lsds, 'generate', os.path.join(HERE, 'road.lscene'), os.path.join(HERE, 'road.lcap'),
        '-o', collection, '--seed', '3', '--spp', '1', '-q')
    frames, classes = collection_frames(collection)

    # Default class numbers (--mot-classes order): car 1, truck 2, person 3 by --classes order.
    out = os.path.join(work, 'out')
    run(lsds, 'convert', collection, '--to', 'mot,visdrone,visdrone-vid', '-o', out, '-q',
        '--classes', 'car,truck,person')
    order = {'car': 1, 'truck': 2, 'person': 3}
    lengths = check_mot_rows(out, frames, classes, order.get)
    score_sequences(out, lengths)
    check_visdrone(out, frames, classes, lengths)

    # MOT17 ids by name: person is MOT17's pedestrian, car 3, truck has no MOT17 id.
    out17 = os.path.join(work, 'out17')
    run(lsds, 'convert', collection, '--to', 'mot', '-o', out17, '-q', '--mot-classes', 'mot17')
    mot17 = {'person': 1, 'car': 3}
    lengths17 = check_mot_rows(out17, frames, classes, mot17.get)
    with open(os.path.join(out17, 'loss_report.json')) as f:
        report = json.load(f)
    trucks = sum(1 for fr in frames.values() for o in fr['objects']
                 if visible(o) and classes[o['class_id']] == 'truck')
    reason = 'mot: not written: the class has no MOT17 id (--mot-classes mot17)'
    check(report['counts'].get(reason, {}).get('total') == trucks,
          'loss report: %s trucks not written, expected %d' %
          (report['counts'].get(reason, {}).get('total'), trucks))
    score_sequences(out17, lengths17, perturb=False)  # class 1: the walker alone

    # Objects below --min-visibility: conf 0 rows (TrackEval drops them from the ground truth, so
    # the considered rows as the tracker still score 1), counted in the loss report.
    out_min = os.path.join(work, 'out_min')
    run(lsds, 'convert', collection, '--to', 'mot', '-o', out_min, '-q',
        '--classes', 'car,truck,person', '--min-visibility', '0.5')
    lengths_min = check_mot_rows(out_min, frames, classes, order.get, min_visibility=0.5)
    score_sequences(out_min, lengths_min, perturb=False)
    hidden = sum(1 for fr in frames.values() for o in fr['objects']
                 if visible(o) and o['visibility'] < 0.5)
    with open(os.path.join(out_min, 'loss_report.json')) as f:
        counts = json.load(f)['counts']
    ignored = counts.get('mot: written with conf 0 (ignored by TrackEval): dropped by a filter', {})
    check(hidden > 0 and ignored.get('total') == hidden,
          'conf 0 rows: %s counted, %d objects below 0.5' % (ignored.get('total'), hidden))

    if FAILURES:
        print('%d failure(s)' % len(FAILURES))
        return 1
    print('ok')
    return 0


if __name__ == '__main__':
    sys.exit(main())

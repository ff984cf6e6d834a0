"""Turns Google Benchmark JSON (map_bench, encode_bench) into bench/README.md's speed table.

Medians only; every row names the anchor measured in the same run and the ratio to it.
Usage: make_table.py map.json encode.json map_1thread.json README.md (rewrites the block between the
<!-- speed-table --> and <!-- /speed-table --> markers)."""
import json
import platform
import re
import sys


def medians(path):
    with open(path) as f:
        data = json.load(f)
    out = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = re.sub(r"(/real_time)?_median$", "", b["name"])
        scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[b["time_unit"]]
        out[name] = (b["real_time"] * scale, b["cpu_time"] * scale)
    return out, data["context"]


# (label, benchmark, anchor label, anchor benchmark, target, bytes moved per frame or None)
MB = 1e6
ROWS = [
    ("map, fisheye view 512×512", "BM_MapBuild/fisheye_512x512", "reference method",
     "BM_Anchor_reference_method/fisheye_512x512", "≤ 1 ms", None),
    ("map, cylindrical 1024×512", "BM_MapBuild/cylindrical_1024x512", "reference method",
     "BM_Anchor_reference_method/cylindrical_1024x512", "≤ 1.5 ms", None),
    ("map, perspective 1024×512", "BM_MapBuild/perspective_1024x512", "reference method",
     "BM_Anchor_reference_method/perspective_1024x512", "≤ 1 ms", None),
    ("map, perspective 1024×512", "BM_MapBuild/perspective_1024x512", "cv::fisheye::initUndistortRectifyMap, 1 camera",
     "BM_Anchor_cv_fisheye_initUndistortRectifyMap_1024x512", "", None),
    # apply: map entries 8 B/px read, output written, ~1 source pixel read per output pixel
    ("apply 1024×512, colour, 2 cameras fused", "BM_Apply/perspective_1024x512_rgb", "cv::remap 16SC2, 1 camera",
     "BM_Anchor_cv_remap_16SC2_linear_1024x512_rgb", "≥ 1.3× cv::remap", 1024 * 512 * (8 + 3 + 3)),
    ("apply 1024×512, grey", "BM_Apply/perspective_1024x512_grey", "cv::remap 16SC2, 1 camera",
     "BM_Anchor_cv_remap_16SC2_linear_1024x512_grey", "≥ 1.3× cv::remap", 1024 * 512 * (8 + 1 + 1)),
    ("apply 2048×1024, colour", "BM_Apply/perspective_2048x1024_rgb", "cv::remap 1024×512 × 4",
     "BM_Anchor_cv_remap_16SC2_linear_1024x512_rgb", "≤ 2.5 ms", 2048 * 1024 * (8 + 3 + 3)),
    ("apply 384×192 colour, shrinking view, footprint-aware (pyramid per frame)",
     "BM_ApplyShrinking/equirect_384x192_rgb_footprint", "same view, bilinear",
     "BM_ApplyShrinking/equirect_384x192_rgb_bilinear", "", None),
    ("JPEG q85 1024×512, colour", "BM_EncodeJpeg/1024x512_rgb", "cv::imencode", "BM_Anchor_cv_imencode_jpeg_1024x512_rgb",
     "", None),
    ("JPEG q85 1024×512, grey", "BM_EncodeJpeg/1024x512_grey", "cv::imencode", "BM_Anchor_cv_imencode_jpeg_1024x512_grey",
     "", None),
    ("PNG 2048×1024, colour (libpng: level 1, SUB, RLE)", "BM_EncodePng/2048x1024_rgb", "cv::imencode, compression 1",
     "BM_Anchor_cv_imencode_png_2048x1024_rgb", "", None),
]


def main():
    figures, context = medians(sys.argv[1])
    encode, _ = medians(sys.argv[2])
    figures.update(encode)
    single, _ = medians(sys.argv[3])
    lines = [
        f"Medians, one run of `bash bench/run_tables.sh` ({context.get('num_cpus')} CPUs at "
        f"{context.get('mhz_per_cpu')} MHz, load average {', '.join(f'{x:.1f}' for x in context.get('load_avg', []))}; "
        f"{platform.machine()}). Ratio: anchor time / ours (> 1: ours faster). First columns: wall "
        "time on 2 threads (JPEG: 1 thread); last columns: CPU time on 1 thread (the reference method "
        "always runs on 1), which a loaded machine disturbs less. GB/s: map entries, output and "
        "~1 source pixel per output pixel, over the 2-thread time.",
        "",
        "| work | ours | anchor, same run | ratio | target | GB/s | 1 thread CPU: ours / anchor | ratio |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, name, anchor_label, anchor, target, traffic in ROWS:
        if name not in figures or anchor not in figures:
            continue
        ours = figures[name][0]
        ref = figures[anchor][0] * (4 if "× 4" in anchor_label else 1)
        gbs = f"{traffic / (ours * 1e-3) / 1e9:.1f}" if traffic else ""
        one = ""
        if name in single and anchor in single:
            ours1 = single[name][1]
            ref1 = single[anchor][1] * (4 if "× 4" in anchor_label else 1)
            one = f"{ours1:.3g} / {ref1:.3g} ms | {ref1 / ours1:.2f}×"
        else:
            one = " | "
        lines.append(f"| {label} | {ours:.3g} ms | {anchor_label}: {ref:.3g} ms | {ref / ours:.2f}× | {target} | {gbs} | {one} |")
    table = "\n".join(lines)
    with open(sys.argv[4]) as f:
        readme = f.read()
    begin, end = "<!-- speed-table -->", "<!-- /speed-table -->"
    if begin not in readme:
        readme += f"\n{begin}\n{end}\n"
    head, rest = readme.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(sys.argv[4], "w") as f:
        f.write(f"{head}{begin}\n{table}\n{end}{tail}")
    print(table)


if __name__ == "__main__":
    main()

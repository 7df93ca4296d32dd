/* The report's index (index.md, index.html): which report figure reproduces
 * which paper figure, the comparison table, the overlay, each log's figures
 * with the paper figure each one names. */
#include <math.h>
#include <string.h>
#include <sys/stat.h>

#include "report.h"

/* What each report figure reproduces, in report_fig order. */
static const struct {
	const char *paper;
	const char *shows;
} fig_info[RF_COUNT] = {
	{"Fig. 3 (ref-energy), 10 (filtered-velocity), 14 (ignore), 16 (improved)",
	 "contact response: (a) position measured and true, whole log in mm and in counts over "
	 "the settled range, (b) velocity, (c) W with E_ref (and E_port when logged), (d) f_pc "
	 "(on its own scale too when small), then W - E_ref, f_c; whole-log signals as min/max "
	 "envelopes"},
	{"Fig. 4", "backward velocity, whole log and zoomed to +-4 counts per period"},
	{"Fig. 5", "zoom at the first one-count velocity sign change while the PC acts after which "
		   "W - E_ref falls"},
	{"Figs. 6 and 7", "force against position: the first press and release against the ideal "
			  "spring; the ticks around the Fig. 5 event"},
	{"Fig. 8", "zoom where the PC becomes active and the next tick does not move"},
	{"Fig. 11", "true against measured position (and the zoom panels) over the log's last "
		    "ticks, the low-velocity phase"},
	{"none (form of Figs. 5, 8)", "zoom at the time given with --zoom T"},
};

static void html_escape(FILE *f, const char *s)
{
	for (; *s; s++) {
		switch (*s) {
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '&': fputs("&amp;", f); break;
		case '"': fputs("&quot;", f); break;
		default: fputc(*s, f);
		}
	}
}

static int file_ok(const char *dir, const char *name, const char *ext)
{
	char path[1400];
	snprintf(path, sizeof path, "%s/%s.%s", dir, name, ext);
	struct stat st;
	return stat(path, &st) == 0 && st.st_size > 0;
}

static const char *pdf_ext(const char *dir, const char *name)
{
	return file_ok(dir, name, "pdf") ? "pdf" : "eps";
}

/* The paper figure one log's figure names, as text. */
static void caption(const report_log *lg, report_fig fig, char *buf, size_t cap)
{
	if (fig == RF_CONTACT) {
		int n = report_contact_paper_fig(lg->sum.variant);
		if (n)
			snprintf(buf, cap, "paper Fig. %d: contact response", n);
		else
			snprintf(buf, cap, "contact response in the form of paper Fig. 3 (no paper "
					   "figure shows this variant)");
	} else if (fig == RF_ZOOM) {
		snprintf(buf, cap, "zoom at t = %.6g s (--zoom)", lg->t_event_s[RW_ZOOM]);
	} else if (fig == RF_FIG5 || fig == RF_FIG8) {
		snprintf(buf, cap, "paper %s: %s (here t = %.4f s)", fig_info[fig].paper,
			 fig_info[fig].shows, lg->t_event_s[fig == RF_FIG5 ? RW_FIG5 : RW_FIG8]);
	} else {
		snprintf(buf, cap, "paper %s: %s", fig_info[fig].paper, fig_info[fig].shows);
	}
}

static void md_figure(FILE *md, FILE *html, const char *dir, const char *file, const char *data,
		      const char *cap, int drawn)
{
	fprintf(md, "**%s**\n\n", cap);
	fputs("<p><b>", html);
	html_escape(html, cap);
	fputs("</b><br>", html);
	if (drawn) {
		fprintf(md, "![%s](%s.png)\n\n[PDF](%s.%s) · [script](%s.gp)", file, file, file,
			pdf_ext(dir, file), file);
		fprintf(html,
			"<img src=\"%s.png\" alt=\"%s\"><br><a href=\"%s.%s\">PDF</a> · <a "
			"href=\"%s.gp\">script</a>",
			file, file, file, pdf_ext(dir, file), file);
	} else {
		fprintf(md, "[script](%s.gp) (not drawn)", file);
		fprintf(html, "<a href=\"%s.gp\">script</a> (not drawn)", file);
	}
	if (data) {
		fprintf(md, " · [data](%s.dat)", data);
		fprintf(html, " · <a href=\"%s.dat\">data</a>", data);
	}
	fputs("\n\n", md);
	fputs("</p>\n", html);
}

static void verdicts(FILE *md, FILE *html, const report_log *lg)
{
	const popc_chatter_result *c = &lg->sum.chatter;
	char text[600];
	size_t len = 0;
	if (!ana_chatter_checked(&lg->sum))
		len += (size_t)snprintf(text + len, sizeof text - len, "Chatter not checked (%s).",
					lg->sum.has_pc_force ? "shorter than one chatter window"
							     : "no PC force");
	else if (c->n_intervals)
		len += (size_t)snprintf(text + len, sizeof text - len,
					"Chatter flagged: %.3f s in %d interval(s).", c->chatter_s,
					c->n_intervals);
	else
		len += (size_t)snprintf(text + len, sizeof text - len, "No chatter flagged.");
	if (!ana_lc_checked(&lg->sum))
		snprintf(text + len, sizeof text - len,
			 " Limit cycle not checked (shorter than half a limit-cycle window).");
	else
		snprintf(text + len, sizeof text - len,
			 " %s: amplitude %.3g m at %.3g Hz over the last %.3g s.",
			 c->limit_cycle ? "Limit cycle" : "No limit cycle", c->lc_amplitude_m,
			 c->lc_frequency_Hz, c->lc_span_s);
	fprintf(md, "%s\n\n", text);
	fputs("<p>", html);
	html_escape(html, text);
	fputs("</p>\n", html);
}

static void compare_html(FILE *html, const report_log *logs, int n)
{
	fputs("<h2>Comparison</h2>\n<table>\n<tr><th>log</th><th>variant</th><th>pc_rms (N)</th>"
	      "<th>pc_rms_late (N)</th><th>pc_max (N)</th><th>pc_active</th><th>W-E_ref end (J)</th>"
	      "<th>vsign/s</th><th>chatter (s)</th><th>limit cycle</th></tr>\n",
	      html);
	for (int i = 0; i < n; i++) {
		const ana_summary *s = &logs[i].sum;
		fprintf(html, "<tr><td><a href=\"#%s\">%s</a></td><td>", logs[i].name, logs[i].name);
		html_escape(html, s->variant);
		fputs("</td>", html);
		/* as compare.md: a cell without data behind it is n/a, never a 0 */
		const struct {
			double v;
			int known;
		} cell[] = {
			{s->pc_rms_N, s->has_pc_force},     {s->pc_rms_late_N, s->has_pc_force},
			{s->pc_max_N, s->has_pc_force},     {s->pc_active, s->has_pc_force},
			{s->w_minus_eref_end_J, s->has_w},  {s->vsign_rate_Hz, 1},
			{s->chatter.chatter_s, ana_chatter_checked(s)},
		};
		for (size_t k = 0; k < sizeof cell / sizeof cell[0]; k++) {
			if (cell[k].known)
				fprintf(html, "<td>%.4g</td>", cell[k].v);
			else
				fputs("<td>n/a</td>", html);
		}
		fprintf(html, "<td>%s</td></tr>\n",
			!ana_lc_checked(s) ? "n/a" : s->chatter.limit_cycle ? "yes" : "no");
	}
	fputs("</table>\n<p><a href=\"compare.csv\">compare.csv</a> · "
	      "<a href=\"compare.md\">compare.md</a></p>\n",
	      html);
}

int report_write_index(const report_out *ro, const report_index *ix, const report_log *logs, int n)
{
	char path[1400], md_path[1400];
	const char *dir = ro->dir;
	FILE *md = report_open(ro, "index.md", md_path, sizeof md_path);
	if (!md)
		return -1;
	FILE *html = report_open(ro, "index.html", path, sizeof path);
	if (!html) {
		fclose(md);
		return -1;
	}
	fprintf(md, "# %s\n\n"
		    "Written by `popc-analyze report`. Each figure has its gnuplot script (`.gp`)\n"
		    "and data (`.dat`) beside it; rerun with `gnuplot NAME.gp` here. Figures name\n"
		    "the figure of Ryu, Hannaford, Kwon, Kim (IEEE T-RO 2005) they reproduce.\n"
		    "Metrics and chatter thresholds: docs/ANALYSIS.md.\n\n"
		    "## Which figure reproduces which paper figure\n\n"
		    "| report figure | paper figure | shows |\n|---|---|---|\n",
		ix->title);
	fputs("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>", html);
	html_escape(html, ix->title);
	fputs("</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
	      "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
	      "td.l{text-align:left}img{max-width:100%}</style></head><body>\n<h1>",
	      html);
	html_escape(html, ix->title);
	fputs("</h1>\n<p>Written by <code>popc-analyze report</code>; each figure's gnuplot script "
	      "(<code>.gp</code>) and data (<code>.dat</code>) are beside it. Figures name the figure "
	      "of Ryu, Hannaford, Kwon, Kim (IEEE T-RO 2005) they reproduce.</p>\n"
	      "<h2>Which figure reproduces which paper figure</h2>\n<table>\n"
	      "<tr><th>report figure</th><th>paper figure</th><th>shows</th></tr>\n",
	      html);
	for (int fg = 0; fg < RF_COUNT; fg++) {
		if (!(ix->figs & (1u << fg)))
			continue;
		fprintf(md, "| `LOG%s.png` | %s | %s |\n", report_fig_suffix[fg], fig_info[fg].paper,
			fig_info[fg].shows);
		fprintf(html, "<tr><td class=\"l\"><code>LOG%s.png</code></td><td class=\"l\">%s</td>"
			      "<td class=\"l\">%s</td></tr>\n",
			report_fig_suffix[fg], fig_info[fg].paper, fig_info[fg].shows);
	}
	if (ix->tables) {
		fputs("| `variants.png` | none (Figs. 3, 14, 16 side by side) | the logs overlaid on "
		      "shared axes: position, W - E_ref, f_pc, f_c |\n",
		      md);
		fputs("<tr><td class=\"l\"><code>variants.png</code></td><td class=\"l\">none (Figs. 3, "
		      "14, 16 side by side)</td><td class=\"l\">the logs overlaid on shared axes: "
		      "position, W - E_ref, f_pc, f_c</td></tr>\n",
		      html);
	}
	fputs("\n", md);
	fputs("</table>\n", html);
	if (ix->tables) {
		fputs("## Comparison\n\n", md);
		ana_summary_print_header(md, ANA_MARKDOWN);
		for (int i = 0; i < n; i++)
			ana_summary_print_row(md, ANA_MARKDOWN, &logs[i].sum);
		fputs("\nAlso as CSV: [compare.csv](compare.csv).\n\n## Variants overlaid\n\n", md);
		compare_html(html, logs, n);
		fputs("<h2>Variants overlaid</h2>\n", html);
		md_figure(md, html, dir, "variants", NULL,
			  "the logs overlaid; force axes shared by every figure of this report",
			  ix->drawn);
	}
	fputs("## Logs\n\n", md);
	fputs("<h2>Logs</h2>\n", html);
	for (int i = 0; i < n; i++) {
		const report_log *lg = &logs[i];
		fprintf(md, "### %s (variant %s)\n\n", lg->name, lg->sum.variant);
		fprintf(html, "<h3 id=\"%s\">%s (variant ", lg->name, lg->name);
		html_escape(html, lg->sum.variant);
		fputs(")</h3>\n", html);
		verdicts(md, html, lg);
		for (int fg = 0; fg < RF_COUNT; fg++) {
			char file[300], data[300], cap[600];
			if (!report_log_has(lg, (report_fig)fg, ix->figs)) {
				if ((ix->figs & (1u << fg)) && (fg == RF_FIG5 || fg == RF_FIG8)) {
					fprintf(md, "No paper Fig. %d event found in this log.\n\n",
						fg == RF_FIG5 ? 5 : 8);
					fprintf(html, "<p>No paper Fig. %d event found in this log.</p>\n",
						fg == RF_FIG5 ? 5 : 8);
				}
				continue;
			}
			snprintf(file, sizeof file, "%s%s", lg->name, report_fig_suffix[fg]);
			snprintf(data, sizeof data, "%s%s", lg->name,
				 fg == RF_CONTACT || fg == RF_FIG4 ? "" : report_fig_suffix[fg]);
			caption(lg, (report_fig)fg, cap, sizeof cap);
			md_figure(md, html, dir, file, data, cap, ix->drawn);
		}
	}
	if (ix->n_own > 0) {
		/* admittance and teleoperation logs: a figure of their own kind,
		 * outside the paper's figures and the comparison */
		fputs("## Logs with figures of their own\n\n", md);
		fputs("<h2>Logs with figures of their own</h2>\n", html);
		for (int i = 0; i < ix->n_own; i++) {
			const report_own *o = &ix->own[i];
			fprintf(md, "### %s (%s log)\n\n", o->name, o->kind);
			fprintf(html, "<h3 id=\"%s\">", o->file);
			html_escape(html, o->name);
			fprintf(html, " (%s log)</h3>\n", o->kind);
			md_figure(md, html, dir, o->file, o->file, o->caption, o->drawn);
		}
	}
	fputs("</body></html>\n", html);
	int bad = report_close(md, md_path, 0) != 0;
	bad |= report_close(html, path, 0) != 0;
	return bad ? -1 : 0;
}

/* The program of every layer link check (tests/layers/meson.build): it does
 * nothing; the check is that it links, with one layer's objects all pulled in
 * (link_whole) and only the layers below it to resolve their calls. */
int main(void)
{
	return 0;
}

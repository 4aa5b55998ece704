#version 450
// @brief Shadow-map casters write depth only.
void main()
{
}

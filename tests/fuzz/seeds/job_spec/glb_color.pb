
glTF*bdptX`’ÍÌÌ=ÍÌL>š™™>º
layers
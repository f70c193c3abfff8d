// Five random bodies of the default model: their statures, and the first written as a glTF file.
// usage: mono Bodies.exe [OUT_DIR]
using System;
using System.IO;
using Sscape;

static class Bodies
{
    static void Main(string[] args)
    {
        string outDir = args.Length > 0 ? args[0] : ".";
        using (Model model = Model.LoadDefault())
        using (Body body = model.CreateBody())
        {
            Console.WriteLine("sscape {0}: {1} vertices, {2} joints, {3} shape components",
                              Library.VersionText, model.VertexCount, model.JointCount, model.ShapeCount);
            int k = model.ShapeCount;
            float[] shapes = model.SampleShapes(5, 1);
            for (int i = 0; i < 5; ++i)
            {
                float[] shape = new float[k];
                Array.Copy(shapes, i * k, shape, 0, k);
                body.Shape = shape;
                Console.WriteLine("body {0}: stature {1:F3} m, waist {2:F3} m, mass {3:F1} kg", i, body.Measure("stature"),
                                  body.Measure("waist_girth"), body.Measure("mass"));
                if (i == 0)
                {
                    string path = Path.Combine(outDir, "body_0.glb");
                    body.Write(path);
                    Console.WriteLine("wrote " + path);
                }
            }
        }
    }
}
